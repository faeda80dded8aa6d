// Sample statistics shared by the studies: one definition of a quantile for every table.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace octarc {

// The q quantiles (0 <= q <= 1) of the finite values, by linear interpolation between order
// statistics: with the n sorted values v_0..v_{n-1}, h = q (n - 1) and the quantile is
// v_floor(h) + (h - floor(h)) (v_floor(h)+1 - v_floor(h)) (numpy's default, "type 7" of
// Hyndman & Fan 1996). NaN when no value is finite. One sort for all of `qs` (a selection each
// for up to four).
inline std::vector<double> sampleQuantiles(std::vector<double> values,
                                           const std::vector<double>& qs) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
      values.end());
  // A few quantiles of many values (a postage stamp's display range) by selection, O(n) each;
  // more by one sort. The order statistics, hence the quantiles, are the same either way.
  const bool select = qs.size() <= 4;
  if (!select) std::sort(values.begin(), values.end());
  auto orderStatistic = [&](std::size_t k) {
    if (select) std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
  };
  std::vector<double> out;
  for (double q : qs) {
    if (values.empty()) {
      out.push_back(std::nan(""));
      continue;
    }
    const double h = std::clamp(q, 0.0, 1.0) * double(values.size() - 1);
    const std::size_t lo = std::size_t(std::floor(h));
    const std::size_t hi = std::min(lo + 1, values.size() - 1);
    const double vLo = orderStatistic(lo);
    // After selecting lo, the next order statistic is the least of the values above it.
    const double vHi = hi == lo ? vLo
                       : select
                           ? *std::min_element(values.begin() + std::ptrdiff_t(hi), values.end())
                           : values[hi];
    out.push_back(vLo + (h - double(lo)) * (vHi - vLo));
  }
  return out;
}

inline double sampleQuantile(std::vector<double> values, double q) {
  return sampleQuantiles(std::move(values), {q}).front();
}

inline double sampleMedian(std::vector<double> values) {
  return sampleQuantile(std::move(values), 0.5);
}

}  // namespace octarc
