#include "octarc/calibration/ColourCut.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "octarc/calibration/LensingFraction.h"
#include "octarc/core/Error.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {

std::string arcColourColumn(const std::string& band) {
  return "ARC_COLOUR_" + band;
}

std::string lensColourColumn(const std::string& band) {
  return "LENS_COLOUR_" + band;
}

void checkColourCutSettings(const ColourCutSettings& s) {
  if (!std::isfinite(s.maxLoMag) || !std::isfinite(s.maxHiMag) || !(s.stepMag > 0) ||
      !(s.maxHiMag >= s.maxLoMag) || (s.maxHiMag - s.maxLoMag) / s.stepMag > 10000.0) {
    throw ConfigError(
        "COLOUR_CUT_MAX: give the lowest and highest MAX and a positive step (mag), lowest <= "
        "highest, at most 10000 steps");
  }
  for (const double level : s.completenessLevels) {
    if (!(level > 0 && level <= 1)) {
      throw ConfigError("colour cut study: completeness levels must be in (0, 1]");
    }
  }
}

ColourCutStudy colourCutStudy(const Table& systems, const std::string& band,
                              const std::string& arcSelection, const ColourCutSettings& s) {
  checkColourCutSettings(s);
  const std::string context = "colour cut study (band " + band + ")";
  const int arcColour = systems.requireColumn(arcColourColumn(band), context);
  const int lensColour = systems.requireColumn(lensColourColumn(band), context);
  const std::vector<double> pass = ColumnExpression(arcSelection, context).evaluate(systems);
  ColourCutStudy out;
  out.band = band;
  out.arcSelection = arcSelection;
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    const double p = pass[std::size_t(r)];
    if (!std::isfinite(p) || p == 0.0) continue;
    ++out.arcs;
    const double difference = systems.value(r, arcColour) - systems.value(r, lensColour);
    if (std::isfinite(difference)) out.differences.push_back(difference);
  }
  std::sort(out.differences.begin(), out.differences.end());
  out.withColours = std::int64_t(out.differences.size());
  // The arcs without both colours are kept at every MAX.
  const std::int64_t alwaysKept = out.arcs - out.withColours;
  const auto steps = std::int64_t(std::floor((s.maxHiMag - s.maxLoMag) / s.stepMag + 1e-9));
  for (std::int64_t k = 0; k <= steps; ++k) {
    ColourCutRow row;
    row.maxMag = s.maxLoMag + double(k) * s.stepMag;
    // Removed when the difference exceeds MAX: kept when difference <= MAX.
    const auto notAbove =
        std::upper_bound(out.differences.begin(), out.differences.end(), row.maxMag);
    row.kept = alwaysKept + std::int64_t(notAbove - out.differences.begin());
    row.fraction = out.arcs > 0 ? double(row.kept) / double(out.arcs) : 0.0;
    row.fractionSigma = binomialSigma(row.kept, out.arcs);
    out.rows.push_back(row);
  }
  for (const double level : s.completenessLevels) {
    ColourCutLevel l;
    l.completeness = level;
    // The fewest arcs to keep, ceil(level * N) (with a tolerance for level * N rounding up a
    // whole number), of which the arcs without colours are kept whatever MAX.
    const auto needed = std::int64_t(std::ceil(level * double(out.arcs) - 1e-9));
    const std::int64_t fromDifferences = needed - alwaysKept;
    if (out.arcs == 0) {
      l.maxMag = std::nan("");
    } else if (fromDifferences <= 0) {
      l.maxMag = -std::numeric_limits<double>::infinity();
    } else {
      l.maxMag = out.differences[std::size_t(fromDifferences - 1)];
    }
    out.levels.push_back(l);
  }
  return out;
}

}  // namespace octarc
