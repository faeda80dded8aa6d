// Small helpers shared by the background estimators (not part of the public API).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Parallel.h"

namespace octarc::detail {

// SExtractor's median of floats: middle value, or the mean of the two middle values (summed in
// float) for an even count. Sorts `v`.
inline float medianInPlace(std::vector<float>& v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  if (n == 0) return 0.0f;
  if (n < 2) return v[0];
  if (n & 1) return v[n / 2];
  const float sum = v[n / 2 - 1] + v[n / 2];
  return static_cast<float>(sum / 2.0);
}

// Pixels that are finite and above SExtractor's blank value -1e30.
inline bool isValidPixel(float v) {
  return std::isfinite(v) && static_cast<double>(v) > -1e30;
}

inline std::int64_t countValid(const ImageF& image, int threads) {
  std::vector<std::int64_t> counts(static_cast<std::size_t>(std::max(threads, 1)), 0);
  const std::int64_t n = image.size();
  const float* p = image.data();
  parallelBlocks(threads, threads, [&](std::int64_t t0, std::int64_t t1) {
    for (std::int64_t t = t0; t < t1; ++t) {
      std::int64_t c = 0;
      for (std::int64_t i = n * t / threads; i < n * (t + 1) / threads; ++i)
        c += isValidPixel(p[i]);
      counts[static_cast<std::size_t>(t)] = c;
    }
  });
  std::int64_t total = 0;
  for (auto c : counts) total += c;
  return total;
}

}  // namespace octarc::detail
