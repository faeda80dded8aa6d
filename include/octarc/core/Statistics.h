// Sample statistics shared by the studies: one definition of a quantile for every table.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
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

// Weighted quantiles of the finite values with finite positive weights (one per value): with the
// values sorted and C_k the sum of the weights up to and including value k, value k sits at
// p_k = (C_k - w_k) / (W - w_last) (W the total), and the q quantile interpolates linearly in
// p. With equal weights p_k = k / (n - 1): sampleQuantiles' definition. NaN when no value is
// left; the value itself when one is.
inline std::vector<double> weightedSampleQuantiles(const std::vector<double>& values,
                                                   const std::vector<double>& weights,
                                                   const std::vector<double>& qs) {
  std::vector<std::pair<double, double>> v;
  for (std::size_t i = 0; i < values.size() && i < weights.size(); ++i) {
    if (std::isfinite(values[i]) && std::isfinite(weights[i]) && weights[i] > 0) {
      v.emplace_back(values[i], weights[i]);
    }
  }
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  if (v.size() <= 1) {
    out.assign(qs.size(), v.empty() ? std::nan("") : v.front().first);
    return out;
  }
  double total = 0;
  for (const auto& e : v) total += e.second;
  const double span = total - v.back().second;
  std::vector<double> p;
  double running = 0;
  for (const auto& e : v) {
    p.push_back(running / span);
    running += e.second;
  }
  p.back() = 1.0;
  for (double q : qs) {
    q = std::clamp(q, 0.0, 1.0);
    const std::size_t hi = std::size_t(std::lower_bound(p.begin(), p.end(), q) - p.begin());
    if (hi == 0) {
      out.push_back(v.front().first);
      continue;
    }
    const std::size_t lo = hi - 1;
    const double t = p[hi] > p[lo] ? (q - p[lo]) / (p[hi] - p[lo]) : 1.0;
    out.push_back(v[lo].first + t * (v[hi].first - v[lo].first));
  }
  return out;
}

// The Wilson score interval of a binomial proportion: k successes in n trials, z standard
// deviations (z = 1: the 68.27 % interval). With p = k / n,
//   centre = (p + z^2 / 2n) / (1 + z^2 / n),
//   half   = z sqrt(p (1 - p) / n + z^2 / 4n^2) / (1 + z^2 / n),
// [centre - half, centre + half], which stays inside [0, 1] and is not empty at k = 0 or n
// (Wilson 1927). n = 0 says nothing: [0, 1].
struct ProportionInterval {
  double low = 0.0, high = 1.0;
};

inline ProportionInterval wilsonInterval(std::int64_t k, std::int64_t n, double z = 1.0) {
  if (n <= 0) return {};
  const double nd = double(n), p = double(k) / nd, z2 = z * z;
  const double denominator = 1.0 + z2 / nd;
  const double centre = (p + z2 / (2.0 * nd)) / denominator;
  const double half = z * std::sqrt(p * (1.0 - p) / nd + z2 / (4.0 * nd * nd)) / denominator;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace octarc
