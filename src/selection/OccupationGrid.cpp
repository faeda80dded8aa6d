#include "octarc/selection/OccupationGrid.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {

OccupationGrid::OccupationGrid(GridBinning binning, std::vector<GridBin> bins,
                               std::unordered_map<BinIndex, std::int64_t> rank,
                               std::int64_t outside, std::int64_t undefined)
    : binning_(std::move(binning)),
      outside_(outside),
      undefined_(undefined),
      bins_(std::move(bins)),
      rank_(std::move(rank)) {
  std::sort(bins_.begin(), bins_.end(), [](const GridBin& a, const GridBin& b) {
    return a.weight != b.weight ? a.weight > b.weight : a.index < b.index;
  });
  for (const GridBin& bin : bins_) {
    binned_ += bin.count;
    binnedWeight_ += bin.weight;
  }
  // Summed in probability order, so the last cumulative is exactly 1.
  double running = 0.0;
  for (std::size_t r = 0; r < bins_.size(); ++r) {
    GridBin& bin = bins_[r];
    running += bin.weight;
    bin.probability = bin.weight / binnedWeight_;
    bin.cumulative = r + 1 == bins_.size() ? 1.0 : running / binnedWeight_;
    rank_[bin.index] = std::int64_t(r);
  }
}

OccupationGrid OccupationGrid::fill(GridBinning binning, const AxisSamples& samples,
                                    const std::vector<double>& weights) {
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
  if (!weights.empty() && weights.size() != n) {
    throw ConfigError("occupation grid filled with " + std::to_string(n) + " samples and " +
                      std::to_string(weights.size()) + " weights");
  }
  // Bin index -> position in `bins` while filling; the constructor turns it into the ranks.
  std::unordered_map<BinIndex, std::int64_t> position;
  std::vector<GridBin> bins;
  std::int64_t outside = 0;
  std::int64_t undefined = 0;
  std::vector<int> k(dims);
  for (std::size_t i = 0; i < n; ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    bool isNan = !(std::isfinite(w) && w > 0.0);
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
      const BinIndex index = binning.pack(k);
      const auto [it, added] = position.emplace(index, std::int64_t(bins.size()));
      if (added) bins.push_back({index, 0, 0.0, 0.0, 0.0});
      GridBin& bin = bins[std::size_t(it->second)];
      ++bin.count;
      bin.weight += w;
    }
  }
  return OccupationGrid(std::move(binning), std::move(bins), std::move(position), outside,
                        undefined);
}

OccupationGrid OccupationGrid::fromCounts(
    GridBinning binning, const std::vector<std::pair<BinIndex, std::int64_t>>& counts,
    std::int64_t outside, std::int64_t undefined) {
  std::vector<GridBin> bins;
  bins.reserve(counts.size());
  for (const auto& [index, count] : counts) {
    if (count < 1) {
      throw ConfigError("occupation grid: bin " + std::to_string(index) + " has count " +
                        std::to_string(count) + " (at least 1)");
    }
    bins.push_back({index, count, double(count), 0.0, 0.0});
  }
  return fromWeights(std::move(binning), bins, outside, undefined);
}

OccupationGrid OccupationGrid::fromWeights(GridBinning binning, const std::vector<GridBin>& bins,
                                           std::int64_t outside, std::int64_t undefined) {
  std::unordered_map<BinIndex, std::int64_t> map;
  map.reserve(bins.size());
  std::vector<GridBin> kept;
  kept.reserve(bins.size());
  for (const GridBin& bin : bins) {
    const std::string name = "occupation grid: bin " + std::to_string(bin.index);
    if (bin.index >= binning.totalBins()) {
      throw ConfigError(name + " outside the " + std::to_string(binning.totalBins()) +
                        " bins of the grid");
    }
    if (bin.count < 1) {
      throw ConfigError(name + " has count " + std::to_string(bin.count) + " (at least 1)");
    }
    if (!(std::isfinite(bin.weight) && bin.weight > 0.0)) {
      throw ConfigError(name + " has weight " + formatNumber(bin.weight, "%.6g") +
                        " (finite and positive)");
    }
    if (!map.emplace(bin.index, 0).second) throw ConfigError(name + " given twice");
    kept.push_back({bin.index, bin.count, bin.weight, 0.0, 0.0});
  }
  if (outside < 0 || undefined < 0) {
    throw ConfigError("occupation grid: negative count of samples outside or undefined");
  }
  return OccupationGrid(std::move(binning), std::move(kept), std::move(map), outside, undefined);
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
