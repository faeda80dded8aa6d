#include "octarc/selection/GridFile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsTable.h"

namespace octarc {

namespace {

constexpr const char* kGridTableName = "OCC_GRID";
constexpr std::int64_t kFormatVersion = 2;
constexpr std::int64_t kOldestVersion = 1;  // no WEIGHT column: the counts are the weights
// Axes a file may describe: AXEXPRnn and DROPAXnn hold two digits in their 8 characters.
constexpr std::int64_t kMaxGridAxes = 99;

std::string numbered(const char* root, std::size_t n) {
  return root + std::to_string(n);
}

void addAxisKeywords(const GridBinning& binning, std::vector<FitsKeyword>& k) {
  k.push_back(FitsKeyword::integer("GRIDDIM", binning.dimensions(), "Axes of the grid"));
  for (std::size_t a = 0; a < binning.axes().size(); ++a) {
    const GridAxis& axis = binning.axes()[a];
    const std::size_t n = a + 1;
    k.push_back(FitsKeyword::text(numbered("AXEXPR", n), axis.expression, "Axis expression"));
    k.push_back(FitsKeyword::real(numbered("AXLO", n), axis.lo, "Axis lower edge (included)"));
    k.push_back(FitsKeyword::real(numbered("AXHI", n), axis.hi, "Axis upper edge (excluded)"));
    k.push_back(FitsKeyword::integer(numbered("AXBINS", n), axis.bins, "Bins along the axis"));
  }
}

FitsTable binsTable(const SavedGrid& saved) {
  const OccupationGrid& grid = saved.grid;
  const std::int64_t dims = grid.binning().dimensions();
  std::vector<std::int32_t> bin;
  std::vector<std::int64_t> count;
  std::vector<double> weight, probability, cumulative;
  std::vector<std::int16_t> selected;
  for (std::size_t r = 0; r < grid.bins().size(); ++r) {
    const GridBin& b = grid.bins()[r];
    for (int k : grid.binning().unpack(b.index)) bin.push_back(k);
    count.push_back(b.count);
    weight.push_back(b.weight);
    probability.push_back(b.probability);
    cumulative.push_back(b.cumulative);
    selected.push_back(saved.contour.selects(std::int64_t(r)) ? 1 : 0);
  }
  FitsTable t;
  t.name = kGridTableName;
  t.columns = {
      {"BIN", "Bin index along each axis (0-based)", "", "", int(dims), std::move(bin), "", ""},
      {"COUNT", "Simulated arcs in the bin", "", "", 1, std::move(count), "", ""},
      {"WEIGHT", "Their SIM_WEIGHT sum", "", "", 1, std::move(weight), "", ""},
      {"PROB", "Probability of the bin", "", "", 1, std::move(probability), "", ""},
      {"CUMPROB", "Contour level at which the bin enters", "", "", 1, std::move(cumulative), "",
       ""},
      {"SELECTED", "1 if in the contour at PLEVEL", "", "", 1, std::move(selected), "", ""},
  };
  auto& k = t.keywords;
  k.push_back(FitsKeyword::integer("OCTGRID", kFormatVersion, "octarc occupation grid version"));
  addAxisKeywords(grid.binning(), k);
  const std::vector<std::string>& dropped = saved.provenance.droppedAxes;
  k.push_back(FitsKeyword::integer("NDROPAX", std::int64_t(dropped.size()),
                                   "Axes dropped to keep the contour connected"));
  for (std::size_t a = 0; a < dropped.size(); ++a) {
    k.push_back(FitsKeyword::text(numbered("DROPAX", a + 1), dropped[a], "Dropped axis"));
  }
  k.push_back(FitsKeyword::real("PLEVEL", saved.contour.level, "Contour level P"));
  k.push_back(FitsKeyword::real("PSELECT", saved.contour.probability, "Held by the contour"));
  k.push_back(FitsKeyword::integer("NSELECT", saved.contour.selectedBins, "Bins in the contour"));
  k.push_back(FitsKeyword::integer("NBINNED", grid.binnedCount(), "Simulated arcs in a bin"));
  k.push_back(FitsKeyword::real("WBINNED", grid.binnedWeight(), "Their SIM_WEIGHT sum"));
  k.push_back(FitsKeyword::integer("NOUTSIDE", grid.outsideCount(), "Arcs outside the ranges"));
  k.push_back(FitsKeyword::integer("NUNDEF", grid.undefinedCount(), "Rows with an axis NaN"));
  k.push_back(FitsKeyword::integer("NOCCUP", grid.occupiedBins(), "Occupied bins"));
  k.push_back(FitsKeyword::text("SPACE", saved.provenance.searchSpace, "Search space"));
  k.push_back(
      FitsKeyword::text("SPACEEXP", saved.provenance.searchSpaceExpression, "Search space cut"));
  addSetupKeywords(saved.provenance.setup, k);
  return t;
}

// Reading -------------------------------------------------------------------------------------

GridBinning readBinning(const FitsTable& t) {
  const std::int64_t dims = t.integer("GRIDDIM", 1, kMaxGridAxes);
  std::vector<GridAxis> axes;
  for (std::int64_t a = 1; a <= dims; ++a) {
    GridAxis axis;
    axis.expression = t.text(numbered("AXEXPR", std::size_t(a)));
    axis.lo = t.number(numbered("AXLO", std::size_t(a)));
    axis.hi = t.number(numbered("AXHI", std::size_t(a)));
    axis.bins = int(t.integer(numbered("AXBINS", std::size_t(a)), 1, kMaxBinsPerAxis));
    axes.push_back(std::move(axis));
  }
  try {
    return GridBinning(std::move(axes));
  } catch (const ConfigError& e) {
    throw IoError(t.where() + ": " + e.what());
  }
}

OccupationGrid readGrid(const FitsTable& t, GridBinning binning) {
  const int dims = binning.dimensions();
  const std::vector<std::int64_t> bin = t.integers("BIN", dims);
  const std::vector<std::int64_t> count = t.integers("COUNT");
  // Version 1 has no weights: every arc weighed 1.
  std::vector<double> weight;
  if (t.findColumn("WEIGHT")) {
    weight = t.doubles("WEIGHT");
  } else {
    for (const std::int64_t c : count) weight.push_back(double(c));
  }
  std::vector<GridBin> bins;
  std::vector<int> k(static_cast<std::size_t>(dims));
  for (std::size_t r = 0; r < count.size(); ++r) {
    for (int a = 0; a < dims; ++a) {
      const std::int64_t v = bin[r * std::size_t(dims) + std::size_t(a)];
      if (v < 0 || v >= binning.axes()[std::size_t(a)].bins) {
        throw IoError(t.where() + ": row " + std::to_string(r + 1) + ": bin index " +
                      std::to_string(v) + " outside axis " + std::to_string(a + 1) + "'s 0.." +
                      std::to_string(binning.axes()[std::size_t(a)].bins - 1));
      }
      k[std::size_t(a)] = int(v);
    }
    bins.push_back({binning.pack(k), count[r], weight[r], 0.0, 0.0});
  }
  try {
    constexpr std::int64_t kMaxCount = std::numeric_limits<std::int64_t>::max();
    OccupationGrid grid =
        OccupationGrid::fromWeights(std::move(binning), bins, t.integer("NOUTSIDE", 0, kMaxCount),
                                    t.integer("NUNDEF", 0, kMaxCount));
    // The rows must be the grid's own order: the file's ranks are what searches report.
    for (std::size_t r = 0; r < bins.size(); ++r) {
      if (grid.bins()[r].index != bins[r].index) {
        throw IoError(t.where() + ": row " + std::to_string(r + 1) +
                      " is out of probability order");
      }
    }
    return grid;
  } catch (const ConfigError& e) {
    throw IoError(t.where() + ": " + e.what());
  }
}

void requireEqual(const FitsTable& t, const char* keyword, std::int64_t stored, std::int64_t actual,
                  const char* what) {
  if (stored != actual) {
    throw IoError(t.where() + ": " + keyword + " = " + std::to_string(stored) + " but the bins " +
                  "table gives " + std::to_string(actual) + " " + what);
  }
}

}  // namespace

void saveGrid(const std::string& path, const SavedGrid& saved) {
  const Contour expected = saved.grid.contour(saved.contour.level);
  if (expected.selectedBins != saved.contour.selectedBins) {
    throw ConfigError(path + ": the contour to save (" +
                      std::to_string(saved.contour.selectedBins) +
                      " bins) is not the grid's contour at its level (" +
                      std::to_string(expected.selectedBins) + " bins)");
  }
  writeFitsTables(path, {binsTable(saved)});
}

SavedGrid loadGrid(const std::string& path) {
  const std::vector<std::string> tables = listFitsTables(path);
  if (std::find(tables.begin(), tables.end(), kGridTableName) == tables.end()) {
    std::string list;
    for (const std::string& name : tables) list += (list.empty() ? "" : ", ") + name;
    throw IoError(path + ": not an occupation grid (no " + kGridTableName + " table" +
                  (list.empty() ? std::string() : "; tables: " + list) + ")");
  }
  const FitsTable t = readFitsTable(path, kGridTableName);
  if (!t.hasKeyword("OCTGRID")) {
    throw IoError(t.where() + ": not an occupation grid (keyword OCTGRID missing)");
  }
  if (t.integer("OCTGRID") < kOldestVersion || t.integer("OCTGRID") > kFormatVersion) {
    throw IoError(t.where() + ": occupation grid format version " +
                  std::to_string(t.integer("OCTGRID")) + " (this octarc reads versions " +
                  std::to_string(kOldestVersion) + " to " + std::to_string(kFormatVersion) + ")");
  }
  OccupationGrid grid = readGrid(t, readBinning(t));
  requireEqual(t, "NOCCUP", t.integer("NOCCUP"), grid.occupiedBins(), "occupied bins");
  requireEqual(t, "NBINNED", t.integer("NBINNED"), grid.binnedCount(), "binned arcs");
  if (t.hasKeyword("WBINNED")) {
    const double stored = t.number("WBINNED"), actual = grid.binnedWeight();
    if (!(std::abs(stored - actual) <= 1e-9 * std::max(1.0, std::abs(actual)))) {
      throw IoError(t.where() + ": WBINNED = " + formatNumber(stored, "%.10g") +
                    " but the bins table gives " + formatNumber(actual, "%.10g") +
                    " binned weight");
    }
  }
  Contour contour;
  try {
    contour = grid.contour(t.number("PLEVEL"));
  } catch (const ConfigError& e) {
    throw IoError(t.where() + ": " + e.what());
  }
  requireEqual(t, "NSELECT", t.integer("NSELECT"), contour.selectedBins, "selected bins");
  const std::vector<std::int64_t> selected = t.integers("SELECTED");
  for (std::size_t r = 0; r < selected.size(); ++r) {
    if ((selected[r] != 0) != contour.selects(std::int64_t(r))) {
      throw IoError(t.where() + ": row " + std::to_string(r + 1) +
                    ": SELECTED disagrees with the contour at PLEVEL");
    }
  }
  GridProvenance provenance{t.text("SPACE"), t.text("SPACEEXP"), readSetup(t), {}};
  if (t.hasKeyword("NDROPAX")) {
    for (std::int64_t a = 1; a <= t.integer("NDROPAX", 0, kMaxGridAxes); ++a) {
      provenance.droppedAxes.push_back(t.text(numbered("DROPAX", std::size_t(a))));
    }
  }
  return SavedGrid{std::move(grid), contour, std::move(provenance)};
}

}  // namespace octarc
