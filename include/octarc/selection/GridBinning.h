// The bins of an occupation-probability grid (METHOD.md section 4): D axes, each an expression
// on catalog columns with a range and a number of bins.
//
// Conventions
//   Bins are half-open: bin k of an axis covers [lo + k w, lo + (k + 1) w), w = (hi - lo) / n,
//   k = 0 .. n-1, so the axis covers [lo, hi). A value is binned as floor((v - lo) n / (hi - lo))
//   (clamped to n - 1 for v just below hi, where rounding could give n). A value below lo, at
//   or above hi, or NaN is in no bin.
//   The packed index of bin (k_0, ..., k_{D-1}) is k_0 + n_0 (k_1 + n_1 (k_2 + ...)): axis 0
//   varies fastest. Packed indices order bins for every tie-break (OccupationGrid).
//   Face neighbours differ by 1 in exactly one axis index (no wrap-around); bins that share
//   only an edge or a corner (diagonal neighbours) are not neighbours.
//   The default axes are METHOD.md's: arcness, anti-arcness, the two skewnesses, the
//   ellipticity e and the decimal logarithm of the isophotal S/N, log10(SNR_ISO).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace octarc {

// Packed bin index (see above).
using BinIndex = std::uint64_t;

struct GridAxis {
  std::string expression;  // on catalog columns (selection/ColumnExpression.h)
  double lo = 0.0;         // the axis covers [lo, hi)
  double hi = 1.0;
  int bins = 1;
};

// The most bins per axis that calibrate's binning search tries (GRID_NBINS) and a grid file may
// hold.
inline constexpr int kMaxBinsPerAxis = 1000;

// METHOD.md section 4's axes: ARCNESS, ANTIARCNESS, SKEW_MAJOR, SKEW_MINOR, E_IMAGE,
// log10(SNR_ISO).
std::vector<std::string> defaultAxisExpressions();

class GridBinning {
 public:
  // Throws ConfigError naming the axis for: no axis, an empty expression, a range that is not
  // finite with lo < hi, fewer than 1 bin, or more than 2^63 bins in all.
  explicit GridBinning(std::vector<GridAxis> axes);

  int dimensions() const { return int(axes_.size()); }
  const std::vector<GridAxis>& axes() const { return axes_; }
  std::uint64_t totalBins() const { return total_; }

  // The bin of value v along `axis`, or -1 when v is outside [lo, hi) or NaN.
  int binOf(int axis, double v) const;
  BinIndex pack(std::span<const int> k) const;
  std::vector<int> unpack(BinIndex index) const;
  // Index along one axis of a packed bin.
  int indexAlong(BinIndex index, int axis) const;
  // The face neighbour one step (+1 or -1) along `axis`, or nullopt at the edge of the grid.
  std::optional<BinIndex> neighbour(BinIndex index, int axis, int step) const;

  // The same axes and ranges with n bins on every axis.
  GridBinning withBins(int n) const;

 private:
  std::vector<GridAxis> axes_;
  std::vector<std::uint64_t> strides_;  // packed-index step of each axis
  std::uint64_t total_ = 1;
};

// Samples of the axis values: samples[a][i] is axis a of sample i (every axis equally long).
using AxisSamples = std::vector<std::vector<double>>;

// The range [lo, hi) of an axis from robust quantiles of its values: lo is the tailFraction
// quantile, hi the (1 - tailFraction) quantile moved up to the next double, so that this value
// is inside. Quantiles interpolate linearly between order statistics (q (n - 1) from the
// smallest, as numpy's default). NaN values are ignored. Throws ConfigError naming `context`
// for fewer than two finite values, a tailFraction outside [0, 0.5) or values all equal.
std::pair<double, double> quantileRange(const std::vector<double>& values, double tailFraction,
                                        const std::string& context);

}  // namespace octarc
