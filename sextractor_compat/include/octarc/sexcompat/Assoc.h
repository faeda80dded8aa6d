// SExtractor's ASSOC: cross-matching the detected objects with an external ASCII list
// (ASSOC_NAME, ASSOC_PARAMS, ASSOC_DATA, ASSOC_RADIUS, ASSOC_TYPE, ASSOCSELEC_TYPE,
// ASSOCCOORD_TYPE), with SExtractor 2.25's rules and quirks (docs SEXTRACTOR.md §6).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/sexcompat/Config.h"

namespace octarc::sexcompat {

enum class AssocType { First, Nearest, Mean, MagMean, Sum, MagSum, Min, Max };
enum class AssocSelection { All, Matched, NotMatched };

struct AssocSettings {
  std::string listPath;     // ASSOC_NAME
  std::vector<int> params;  // ASSOC_PARAMS: 1-based columns of x, y[, weight]
  std::vector<int> data;    // ASSOC_DATA: 1-based columns copied to VECTOR_ASSOC; 0 = all
  double radiusPix = 2.0;   // ASSOC_RADIUS
  AssocType type = AssocType::Nearest;
  AssocSelection selection = AssocSelection::Matched;
  bool worldCoordinates = false;  // ASSOCCOORD_TYPE WORLD: x, y are (lng, lat) in degrees

  static AssocSettings fromConfig(const Config& config);
};

class AssocList {
 public:
  // Reads the list. `vectorSize` is n of VECTOR_ASSOC(n) in the .param file (0 if only
  // NUMBER_ASSOC is requested); it shrinks, with a warning, when fewer data columns exist.
  // `naxis2` is the image height (objects in the top half-row never match, as in SExtractor).
  // worldToPixel converts (lng, lat) degrees -> 1-based pixel; needed only for ASSOCCOORD_TYPE
  // WORLD. Lines whose first character is '#' or TAB, and empty lines, are skipped (a line
  // starting with a space is data); the first data line sets the column count. Without a weight
  // column, MEAN, MAG_MEAN, MIN and MAX fall back to FIRST with a warning. Throws IoError for a
  // missing file and ConfigError "<file>:<line>: ..." for a non-numeric field, too few fields or
  // an ASSOC_PARAMS/ASSOC_DATA column beyond the list. `warnings` may be null.
  static AssocList load(const AssocSettings& settings, int vectorSize, std::int64_t naxis2,
                        const std::function<std::array<double, 2>(double, double)>& worldToPixel,
                        std::vector<std::string>* warnings);

  struct Match {
    int count = 0;               // NUMBER_ASSOC
    std::vector<double> values;  // VECTOR_ASSOC, vectorSize() values, zero-filled if no match
  };
  // Matches an object at 1-based (X_IMAGE, Y_IMAGE): entries with dx^2 + dy^2 < r^2 (strict).
  Match match(double xFits, double yFits) const;
  // Whether an object with this match is kept by ASSOCSELEC_TYPE.
  bool keeps(const Match& m) const;

  int vectorSize() const { return vectorSize_; }
  AssocType type() const { return type_; }  // after the FIRST fallback
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    double x = 0, y = 0, weight = 0;  // 1-based pixel position; weight 0 without a weight column
    std::vector<double> data;         // vectorSize_ values
  };
  std::vector<Entry> entries_;  // sorted by y (stable)
  int vectorSize_ = 0;
  double radiusPix_ = 2.0;
  AssocType type_ = AssocType::Nearest;
  AssocSelection selection_ = AssocSelection::Matched;
  std::int64_t naxis2_ = 0;
};

// Catalog metadata of VECTOR_ASSOC(n) and NUMBER_ASSOC, as SExtractor declares them.
ColumnSpec vectorAssocColumn(int n);
ColumnSpec numberAssocColumn();

}  // namespace octarc::sexcompat
