// Whole-image kappa-sigma clipped background. Each clipping step reads the image twice: once for
// the moments (double sums about a local origin, in fixed 64 Ki-pixel chunks so that the
// rounding does not depend on the thread count) and a 65 536-bin histogram of the high half of
// each float's order-preserving key, then once for the low half inside the median's bin. This
// gives the exact median without copying or sorting the image.
#include "octarc/background/GlobalBackground.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "BackgroundDetail.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

constexpr std::int64_t kChunk = 1 << 16;
constexpr int kBins = 1 << 16;

// Monotone map float -> uint32 (for finite values): a < b  <=>  key(a) < key(b), except that
// -0 sorts just below +0.
inline std::uint32_t orderKey(float v) {
  const std::uint32_t u = std::bit_cast<std::uint32_t>(v);
  return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}
inline float fromOrderKey(std::uint32_t k) {
  const std::uint32_t u = (k & 0x80000000u) ? (k & 0x7fffffffu) : ~k;
  return std::bit_cast<float>(u);
}

struct ChunkMoments {
  std::int64_t n = 0;
  double sum = 0.0;    // sum of (v - origin)
  double sumSq = 0.0;  // sum of (v - origin)^2
  float min = std::numeric_limits<float>::infinity();
  float max = -std::numeric_limits<float>::infinity();
};

struct Selection {
  std::int64_t n = 0;
  double mean = 0.0;
  double sigma = 0.0;
  double median = 0.0;
  float min = 0.0f;
  float max = 0.0f;
};

inline bool inRange(float v, double lo, double hi) {
  return detail::isValidPixel(v) && static_cast<double>(v) >= lo && static_cast<double>(v) <= hi;
}

// Rank r (0-based) inside a histogram: the bin holding it and the rank within that bin.
void locate(const std::vector<std::int64_t>& histo, std::int64_t r, int& bin, std::int64_t& rest) {
  std::int64_t below = 0;
  for (int b = 0; b < kBins; ++b) {
    if (below + histo[static_cast<std::size_t>(b)] > r) {
      bin = b;
      rest = r - below;
      return;
    }
    below += histo[static_cast<std::size_t>(b)];
  }
  bin = kBins - 1;
  rest = 0;
}

// Moments and exact median of the valid pixels with lo <= v <= hi.
Selection select(const ImageF& image, double lo, double hi, double origin, int threads) {
  const float* p = image.data();
  const std::int64_t n = image.size();
  const std::int64_t nChunks = (n + kChunk - 1) / kChunk;
  std::vector<ChunkMoments> chunks(static_cast<std::size_t>(nChunks));
  std::vector<std::vector<std::int64_t>> high(static_cast<std::size_t>(threads),
                                              std::vector<std::int64_t>(kBins, 0));
  parallelBlocks(threads, threads, [&](std::int64_t t0, std::int64_t t1) {
    for (std::int64_t t = t0; t < t1; ++t) {
      auto& h = high[static_cast<std::size_t>(t)];
      for (std::int64_t c = nChunks * t / threads; c < nChunks * (t + 1) / threads; ++c) {
        ChunkMoments m;
        const std::int64_t end = std::min(n, (c + 1) * kChunk);
        for (std::int64_t i = c * kChunk; i < end; ++i) {
          const float v = p[i];
          if (!inRange(v, lo, hi)) continue;
          const double d = static_cast<double>(v) - origin;
          ++m.n;
          m.sum += d;
          m.sumSq += d * d;
          m.min = std::min(m.min, v);
          m.max = std::max(m.max, v);
          ++h[orderKey(v) >> 16];
        }
        chunks[static_cast<std::size_t>(c)] = m;
      }
    }
  });

  Selection s;
  ChunkMoments total;
  for (const auto& m : chunks) {
    total.n += m.n;
    total.sum += m.sum;
    total.sumSq += m.sumSq;
    total.min = std::min(total.min, m.min);
    total.max = std::max(total.max, m.max);
  }
  s.n = total.n;
  if (s.n == 0) return s;
  const double meanOffset = total.sum / static_cast<double>(s.n);
  const double var = total.sumSq / static_cast<double>(s.n) - meanOffset * meanOffset;
  s.mean = origin + meanOffset;
  s.sigma = var > 0.0 ? std::sqrt(var) : 0.0;
  s.min = total.min;
  s.max = total.max;

  std::vector<std::int64_t> highTotal(kBins, 0);
  for (const auto& h : high)
    for (int b = 0; b < kBins; ++b)
      highTotal[static_cast<std::size_t>(b)] += h[static_cast<std::size_t>(b)];

  // The two middle ranks (equal for odd n) and their high-half bins.
  const std::array<std::int64_t, 2> ranks{(s.n - 1) / 2, s.n / 2};
  std::array<int, 2> bins{};
  std::array<std::int64_t, 2> rest{};
  for (int r = 0; r < 2; ++r)
    locate(highTotal, ranks[static_cast<std::size_t>(r)], bins[r], rest[r]);

  // Second pass: low halves of the keys inside those bins.
  std::vector<std::vector<std::int64_t>> low(static_cast<std::size_t>(threads) * 2,
                                             std::vector<std::int64_t>(kBins, 0));
  parallelBlocks(threads, threads, [&](std::int64_t t0, std::int64_t t1) {
    for (std::int64_t t = t0; t < t1; ++t) {
      auto& l0 = low[static_cast<std::size_t>(2 * t)];
      auto& l1 = low[static_cast<std::size_t>(2 * t + 1)];
      for (std::int64_t i = n * t / threads; i < n * (t + 1) / threads; ++i) {
        const float v = p[i];
        if (!inRange(v, lo, hi)) continue;
        const std::uint32_t k = orderKey(v);
        const int hb = static_cast<int>(k >> 16);
        if (hb == bins[0]) ++l0[k & 0xffffu];
        if (hb == bins[1]) ++l1[k & 0xffffu];
      }
    }
  });
  std::array<float, 2> values{};
  for (int r = 0; r < 2; ++r) {
    std::vector<std::int64_t> lowTotal(kBins, 0);
    for (int t = 0; t < threads; ++t) {
      const auto& l = low[static_cast<std::size_t>(2 * t + r)];
      for (int b = 0; b < kBins; ++b)
        lowTotal[static_cast<std::size_t>(b)] += l[static_cast<std::size_t>(b)];
    }
    int lowBin = 0;
    std::int64_t unused = 0;
    locate(lowTotal, rest[r], lowBin, unused);
    values[r] = fromOrderKey((static_cast<std::uint32_t>(bins[r]) << 16) |
                             static_cast<std::uint32_t>(lowBin));
  }
  s.median = 0.5 * (static_cast<double>(values[0]) + static_cast<double>(values[1]));
  return s;
}

}  // namespace

GlobalBackground estimateGlobalBackground(const ImageF& image, double clipSigma, int maxIterations,
                                          std::string_view imageName, int threadCount) {
  const std::string name(imageName);
  if (!(clipSigma > 0.0))
    throw ConfigError("clipSigma: the clipping factor must be positive, got " +
                      std::to_string(clipSigma));
  if (maxIterations < 0)
    throw ConfigError("maxIterations: must be >= 0, got " + std::to_string(maxIterations));
  int threads = resolveThreads(threadCount);

  // Local origin for the sums: the first valid pixel, then the current median.
  double origin = 0.0;
  bool found = false;
  for (std::int64_t i = 0; i < image.size() && !found; ++i)
    if (detail::isValidPixel(image[i])) {
      origin = image[i];
      found = true;
    }
  if (!found)
    throw IoError(name +
                  ": no valid pixels (all NaN, infinite or blank), cannot estimate the "
                  "background");

  const double inf = std::numeric_limits<double>::infinity();
  GlobalBackground result;
  Selection s = select(image, -inf, inf, origin, threads);
  int steps = 0;
  bool converged = false;
  while (steps < maxIterations) {
    if (s.sigma <= 0.0) {  // constant data: nothing to clip
      converged = true;
      break;
    }
    const double lo = s.median - clipSigma * s.sigma;
    const double hi = s.median + clipSigma * s.sigma;
    Selection next = select(image, lo, hi, s.median, threads);
    ++steps;
    // A selection is all valid pixels between its extreme values, so equal extremes mean an
    // unchanged set.
    const bool same = next.n == s.n && next.min == s.min && next.max == s.max;
    s = next;
    if (same) {
      converged = true;
      break;
    }
  }

  result.meanAdu = s.mean;
  result.medianAdu = s.median;
  result.pixelCount = s.n;
  result.iterations = steps;
  result.converged = converged;
  if (s.sigma > 0.0) {
    result.sigmaAdu = s.sigma;
    result.levelAdu =
        std::fabs(s.mean - s.median) < 0.3 * s.sigma ? 2.5 * s.median - 1.5 * s.mean : s.median;
  } else {
    result.sigmaAdu = 1.0;
    result.levelAdu = s.median;
    result.warning = name + ": image contains constant data; background noise sigma set to 1";
  }
  return result;
}

}  // namespace octarc
