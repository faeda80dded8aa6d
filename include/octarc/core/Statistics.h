// Sample statistics shared by the studies: one definition of a quantile for every table.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace octarc {

// The q quantile (0 <= q <= 1) of the finite values, by linear interpolation between order
// statistics: with the n sorted values v_0..v_{n-1}, h = q (n - 1) and the quantile is
// v_floor(h) + (h - floor(h)) (v_floor(h)+1 - v_floor(h)) (numpy's default, "type 7" of
// Hyndman & Fan 1996). NaN when no value is finite.
inline double sampleQuantile(std::vector<double> values, double q) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
      values.end());
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const double h = std::clamp(q, 0.0, 1.0) * double(values.size() - 1);
  const std::size_t lo = std::size_t(std::floor(h));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (h - double(lo)) * (values[hi] - values[lo]);
}

inline double sampleMedian(std::vector<double> values) {
  return sampleQuantile(std::move(values), 0.5);
}

}  // namespace octarc
