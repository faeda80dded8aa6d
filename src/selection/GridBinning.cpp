#include "octarc/selection/GridBinning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Statistics.h"

namespace octarc {

namespace {

// Packed indices stay below 2^63, so that they also fit a signed 64-bit FITS column.
constexpr std::uint64_t kMaxTotalBins = std::uint64_t(1) << 63;

std::string axisName(std::size_t a, const GridAxis& axis) {
  return "grid axis " + std::to_string(a + 1) + " (" + axis.expression + ")";
}

}  // namespace

std::vector<std::string> defaultAxisExpressions() {
  return {"ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR", "E_IMAGE", "log10(SNR_ISO)"};
}

GridBinning::GridBinning(std::vector<GridAxis> axes) : axes_(std::move(axes)) {
  if (axes_.empty()) throw ConfigError("an occupation grid needs at least one axis");
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    const GridAxis& axis = axes_[a];
    if (axis.expression.find_first_not_of(" \t") == std::string::npos) {
      throw ConfigError("grid axis " + std::to_string(a + 1) + " has no expression");
    }
    if (!std::isfinite(axis.lo) || !std::isfinite(axis.hi) || !(axis.lo < axis.hi)) {
      throw ConfigError(axisName(a, axis) + ": range [" + std::to_string(axis.lo) + ", " +
                        std::to_string(axis.hi) + ") is not a finite range with lo < hi");
    }
    if (axis.bins < 1) {
      throw ConfigError(axisName(a, axis) + ": " + std::to_string(axis.bins) +
                        " bins (at least 1)");
    }
    strides_.push_back(total_);
    if (total_ > kMaxTotalBins / std::uint64_t(axis.bins)) {
      throw ConfigError("occupation grid: more than 2^63 bins in all (at " + axisName(a, axis) +
                        ")");
    }
    total_ *= std::uint64_t(axis.bins);
  }
}

int GridBinning::binOf(int axis, double v) const {
  const GridAxis& a = axes_[std::size_t(axis)];
  if (!(v >= a.lo && v < a.hi)) return -1;  // also NaN
  const double k = std::floor((v - a.lo) * a.bins / (a.hi - a.lo));
  return std::min(int(k), a.bins - 1);
}

BinIndex GridBinning::pack(std::span<const int> k) const {
  BinIndex index = 0;
  for (std::size_t a = 0; a < axes_.size(); ++a) index += BinIndex(k[a]) * strides_[a];
  return index;
}

std::vector<int> GridBinning::unpack(BinIndex index) const {
  std::vector<int> k(axes_.size());
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    k[a] = int(index % std::uint64_t(axes_[a].bins));
    index /= std::uint64_t(axes_[a].bins);
  }
  return k;
}

int GridBinning::indexAlong(BinIndex index, int axis) const {
  return int((index / strides_[std::size_t(axis)]) % std::uint64_t(axes_[std::size_t(axis)].bins));
}

std::optional<BinIndex> GridBinning::neighbour(BinIndex index, int axis, int step) const {
  const int k = indexAlong(index, axis) + step;
  if (k < 0 || k >= axes_[std::size_t(axis)].bins) return std::nullopt;
  const std::uint64_t stride = strides_[std::size_t(axis)];
  return step > 0 ? index + stride : index - stride;
}

GridBinning GridBinning::withBins(int n) const {
  std::vector<GridAxis> axes = axes_;
  for (GridAxis& a : axes) a.bins = n;
  return GridBinning(std::move(axes));
}

std::pair<double, double> quantileRange(const std::vector<double>& values, double tailFraction,
                                        const std::string& context) {
  if (!(tailFraction >= 0.0 && tailFraction < 0.5)) {
    throw ConfigError(context + ": tail fraction " + std::to_string(tailFraction) +
                      " outside [0, 0.5)");
  }
  std::vector<double> finite;
  finite.reserve(values.size());
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  if (finite.size() < 2) {
    throw ConfigError(context + ": " + std::to_string(finite.size()) +
                      " finite values, too few to choose a range");
  }
  const std::vector<double> q =
      sampleQuantiles(std::move(finite), {tailFraction, 1.0 - tailFraction});
  const double lo = q[0], top = q[1];
  if (!(lo < top)) {
    throw ConfigError(context + ": the values between the quantiles are all equal (" +
                      std::to_string(lo) + "), no range to bin");
  }
  return {lo, std::nextafter(top, std::numeric_limits<double>::infinity())};
}

}  // namespace octarc
