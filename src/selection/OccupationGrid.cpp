#include "octarc/selection/OccupationGrid.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {

namespace {}  // namespace

OccupationGrid::OccupationGrid(GridBinning binning,
                               std::unordered_map<BinIndex, std::int64_t> counts,
                               std::int64_t outside, std::int64_t undefined)
    : binning_(std::move(binning)), outside_(outside), undefined_(undefined) {
  bins_.reserve(counts.size());
  for (const auto& [index, count] : counts) {
    bins_.push_back({index, count, 0.0, 0.0});
    binned_ += count;
  }
  std::sort(bins_.begin(), bins_.end(), [](const GridBin& a, const GridBin& b) {
    return a.count != b.count ? a.count > b.count : a.index < b.index;
  });
  // The map that held the counts now holds the ranks: no second map.
  rank_ = std::move(counts);
  std::int64_t running = 0;
  for (std::size_t r = 0; r < bins_.size(); ++r) {
    GridBin& bin = bins_[r];
    running += bin.count;
    bin.probability = double(bin.count) / double(binned_);
    bin.cumulative = double(running) / double(binned_);
    rank_[bin.index] = std::int64_t(r);
  }
}

OccupationGrid OccupationGrid::fill(GridBinning binning, const AxisSamples& samples) {
  const std::size_t dims = std::size_t(binning.dimensions());
  if (samples.size() != dims) {
    throw ConfigError("occupation grid of " + std::to_string(dims) + " axes filled with " +
                      std::to_string(samples.size()) + " axes of values");
  }
  const std::size_t n = samples[0].size();
  for (const std::vector<double>& axis : samples) {
    if (axis.size() != n) {
      throw ConfigError("occupation grid filled with axes of different lengths (" +
                        std::to_string(n) + " and " + std::to_string(axis.size()) + ")");
    }
  }
  std::unordered_map<BinIndex, std::int64_t> counts;
  std::int64_t outside = 0;
  std::int64_t undefined = 0;
  std::vector<int> k(dims);
  for (std::size_t i = 0; i < n; ++i) {
    bool isNan = false;
    bool isOutside = false;
    for (std::size_t a = 0; a < dims; ++a) {
      const double v = samples[a][i];
      isNan = isNan || std::isnan(v);
      k[a] = binning.binOf(int(a), v);
      isOutside = isOutside || k[a] < 0;
    }
    if (isNan) {
      ++undefined;
    } else if (isOutside) {
      ++outside;
    } else {
      ++counts[binning.pack(k)];
    }
  }
  return OccupationGrid(std::move(binning), std::move(counts), outside, undefined);
}

OccupationGrid OccupationGrid::fromCounts(
    GridBinning binning, const std::vector<std::pair<BinIndex, std::int64_t>>& counts,
    std::int64_t outside, std::int64_t undefined) {
  std::unordered_map<BinIndex, std::int64_t> map;
  map.reserve(counts.size());
  for (const auto& [index, count] : counts) {
    if (index >= binning.totalBins()) {
      throw ConfigError("occupation grid: bin " + std::to_string(index) + " outside the " +
                        std::to_string(binning.totalBins()) + " bins of the grid");
    }
    if (count < 1) {
      throw ConfigError("occupation grid: bin " + std::to_string(index) + " has count " +
                        std::to_string(count) + " (at least 1)");
    }
    if (!map.emplace(index, count).second) {
      throw ConfigError("occupation grid: bin " + std::to_string(index) + " given twice");
    }
  }
  if (outside < 0 || undefined < 0) {
    throw ConfigError("occupation grid: negative count of samples outside or undefined");
  }
  return OccupationGrid(std::move(binning), std::move(map), outside, undefined);
}

std::int64_t OccupationGrid::rankOf(BinIndex index) const {
  const auto it = rank_.find(index);
  return it == rank_.end() ? -1 : it->second;
}

std::optional<BinIndex> OccupationGrid::binOf(std::span<const double> values) const {
  if (values.size() != std::size_t(binning_.dimensions())) {
    throw ConfigError("a point of " + std::to_string(values.size()) + " values for a grid of " +
                      std::to_string(binning_.dimensions()) + " axes");
  }
  std::vector<int> k(values.size());
  for (std::size_t a = 0; a < values.size(); ++a) {
    k[a] = binning_.binOf(int(a), values[a]);
    if (k[a] < 0) return std::nullopt;
  }
  return binning_.pack(k);
}

Contour OccupationGrid::contour(double level) const {
  if (!(level > 0.0 && level <= 1.0)) {
    throw ConfigError("contour level P = " + formatNumber(level, "%.6g") + " outside (0, 1]");
  }
  if (bins_.empty()) {
    throw ConfigError("the contour at P = " + formatNumber(level, "%.6g") +
                      " selects nothing: no simulated arc fell in a bin of the grid (" +
                      std::to_string(outside_) + " outside the axis ranges, " +
                      std::to_string(undefined_) + " undefined)");
  }
  // The cumulative never decreases and the last one is exactly 1, so a first rank with
  // cumulative >= level always exists.
  const auto first =
      std::lower_bound(bins_.begin(), bins_.end(), level,
                       [](const GridBin& bin, double p) { return bin.cumulative < p; });
  Contour c;
  c.level = level;
  c.selectedBins = std::int64_t(first - bins_.begin()) + 1;
  c.probability = first->cumulative;
  return c;
}

std::vector<BinIndex> OccupationGrid::selectedIndices(const Contour& contour) const {
  std::vector<BinIndex> out;
  const std::size_t n = std::min(std::size_t(contour.selectedBins), bins_.size());
  out.reserve(n);
  for (std::size_t r = 0; r < n; ++r) out.push_back(bins_[r].index);
  return out;
}

AxisSamples evaluateAxes(const std::vector<std::string>& expressions, const Table& table,
                         const std::vector<bool>& mask) {
  if (!mask.empty() && mask.size() != std::size_t(table.rows())) {
    throw ConfigError("row mask of " + std::to_string(mask.size()) + " rows for a table of " +
                      std::to_string(table.rows()));
  }
  AxisSamples samples;
  for (std::size_t a = 0; a < expressions.size(); ++a) {
    const ColumnExpression axis(expressions[a], "grid axis " + std::to_string(a + 1));
    std::vector<double> all = axis.evaluate(table);
    if (mask.empty()) {
      samples.push_back(std::move(all));
      continue;
    }
    std::vector<double> kept;
    for (std::size_t r = 0; r < all.size(); ++r) {
      if (mask[r]) kept.push_back(all[r]);
    }
    samples.push_back(std::move(kept));
  }
  return samples;
}

}  // namespace octarc
