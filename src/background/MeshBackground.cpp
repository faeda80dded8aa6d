// SExtractor-compatible mesh background. The arithmetic deliberately follows source-extractor
// 2.25 operation by operation, including its float/double mix and summation order, so that on
// the same pixel values the maps agree with SExtractor's bit for bit (the detection thresholds
// and hence the segmentation depend on them); comments mark the places where that matters.
#include "octarc/background/MeshBackground.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <thread>
#include <type_traits>

#include "BackgroundDetail.h"
#include "octarc/background/MeshHistogram.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

constexpr std::int64_t kStatBuffer = 1048576;  // pixels per mesh row beyond which rows are sampled
constexpr double kMinGoodFraction = 0.5;       // a mesh needs this fraction of valid pixels
constexpr double kHistSigmas = 5.0;            // histogram spans mean +- 5 sigma
constexpr int kMaxHistLevels = 4096;
constexpr double kMinModePixels = 4.0;  // pixels per histogram bin near the mode (on average)
// SExtractor's value of pi (its define.h); it sets the number of histogram bins.
constexpr double kSexPi = 3.1415926535898;

// The float nearest to SExtractor's blank value -1e30 lies below it, so a float v is above -1e30
// (as a double) exactly when v > kBlankFloat: no float lies between the two.
constexpr float kBlankFloat = -1e30f;
static_assert(static_cast<double>(kBlankFloat) < -1e30);

// Statistics of one mesh, kept in SExtractor's precision (floats).
struct MeshStat {
  float mean = 0.0f;
  float sigma = 0.0f;
  float qzero = 0.0f;
  float qscale = 1.0f;
  int nlevels = 0;
};

// Clipped mode and rms from a mesh histogram (SExtractor's backguess).
void histogramMode(const MeshStat& m, std::span<const std::int64_t> histo,
                   std::vector<std::uint64_t>& scratch, float& level, float& rms) {
  const MeshMode mode =
      meshHistogramMode(histo, MeshHistogramScale{m.mean, m.qzero, m.qscale}, scratch);
  level = mode.levelAdu;
  rms = mode.rmsAdu;
}

// Mean/sigma of a set of pixels, then the SExtractor histogram parameters derived from them.
void finishStat(MeshStat& m, double sum, double sumSq, std::int64_t npix) {
  const double levelStep = std::sqrt(2.0 / kSexPi) * kHistSigmas / kMinModePixels;
  const double mean = sum / static_cast<double>(npix);
  const double var = sumSq / static_cast<double>(npix) - mean * mean;
  const double sigma = var > 0.0 ? std::sqrt(var) : 0.0;
  m.mean = static_cast<float>(mean);
  m.sigma = static_cast<float>(sigma);
  m.nlevels = std::min(static_cast<int>(levelStep * static_cast<double>(npix) + 1), kMaxHistLevels);
  m.qscale = sigma > 0.0 ? static_cast<float>(2 * kHistSigmas * sigma / m.nlevels) : 1.0f;
  m.qzero = static_cast<float>(mean - kHistSigmas * sigma);
}

// Histogram bin as SExtractor computes it, in float: (int)(v / qscale + 0.499999 - qzero /
// qscale); values in (-1, 0) truncate to bin 0. Returns -1 outside the histogram.
struct Binner {
  float qscale, offset, top;
  explicit Binner(const MeshStat& m)
      : qscale(m.qscale),
        offset(static_cast<float>(0.499999 - m.qzero / m.qscale)),
        top(static_cast<float>(m.nlevels)) {}
  int operator()(float v) const {
    const float b = v / qscale + offset;
    return (b > -1.0f && b < top) ? static_cast<int>(b) : -1;
  }
  // The bin shifted by one into a histogram with a spare bin at each end: 0 below, nlevels + 1
  // above (and for NaN). The value is clamped before the conversion, so that no out-of-range
  // float is converted and the loop over a row has no branch (it vectorises).
  int shiftedIndex(float v) const {
    float b = v / qscale + offset;
    b = b > -1.0f ? b : -1.0f;
    b = b < top ? b : top;
    return static_cast<int>(b) + 1;
  }
};

// Sums of the pixels that pass `keep`, for K meshes of width mw side by side: mesh k starts at
// p + k * meshStride, and rowStride separates the rows used. Each mesh has its own summation
// chain in SExtractor's order (row by row, left to right), so the sums are bit-identical to one
// mesh at a time, while the processor overlaps the K chains. A rejected pixel adds +0.0, which
// leaves a sum that started at +0.0 unchanged, so there is no branch.
template <int K, typename Keep>
void maskedSums(const float* p, std::int64_t rowStride, int rows, int mw, std::int64_t meshStride,
                Keep keep, double* sum, double* sumSq, std::int64_t* npix) {
  double s[K], q[K];
  std::int64_t n[K];
  for (int k = 0; k < K; ++k) {
    s[k] = q[k] = 0.0;
    n[k] = 0;
  }
  for (int r = 0; r < rows; ++r, p += rowStride) {
#if defined(__GNUC__)
    // Successive rows of a group are a whole image row apart (16 KB for 4096 pixels), a jump
    // the hardware prefetchers do not follow: ask for the row after next, one cache line at a
    // time. This pass is the first to read the pixels of a mesh row.
    if (r + 2 < rows) {
      const float* ahead = p + 2 * rowStride;
      for (std::int64_t o = 0; o < (K - 1) * meshStride + mw; o += 16)
        __builtin_prefetch(ahead + o);
    }
#endif
    for (int x = 0; x < mw; ++x) {
      for (int k = 0; k < K; ++k) {
        const float v = p[k * meshStride + x];
        const bool ok = keep(k, v);
        // The selection by bit mask rather than `ok ? v : 0.0`, which compilers turn into a
        // branch that the noise in the cut pass mispredicts.
        const double d = std::bit_cast<double>(
            std::bit_cast<std::uint64_t>(static_cast<double>(v)) & (std::uint64_t{0} - ok));
        s[k] += d;
        q[k] += d * d;
        n[k] += ok;
      }
    }
  }
  for (int k = 0; k < K; ++k) {
    sum[k] = s[k];
    sumSq[k] = q[k];
    npix[k] = n[k];
  }
}

// SExtractor's weight_to_var: a weight-map pixel as a variance, for a given scale^2 (float).
inline float toVariance(WeightMapType type, float v, float scale2) {
  switch (type) {
    case WeightMapType::Weight:
      return v > 0.0f ? scale2 / v : 1e30f;
    case WeightMapType::Rms:
      return static_cast<double>(v) < 1e30 ? v * v : v;
    case WeightMapType::Variance:
      return v * scale2;
  }
  return v;
}

// The variance-like maps of one mesh row, when a weight map is used.
struct WeightRow {
  const ImageF* map = nullptr;  // the weight map as given
  WeightMapType type = WeightMapType::Weight;
  float threshold = 0.0f;  // pixels with variance >= threshold are ignored
  float* level = nullptr;  // mesh mode of the variance map
  float* rms = nullptr;
};

// Rows of a mesh row used for the mean/sigma statistics: all of them, or an evenly spaced subset
// when a mesh row is larger than SExtractor's statistics buffer.
struct StatRows {
  int first = 0, step = 1, count = 0;
  StatRows(std::int64_t w, int bh, int rows) : count(rows) {
    if (w * bh > kStatBuffer) {
      const int maxLines = static_cast<int>(std::max<std::int64_t>(1, kStatBuffer / w));
      step = (rows - 1) / maxLines + 1;
      count = rows / step;
      first = step / 2;
    }
  }
};

// The mesh statistics of measureMeshRow without a weight map. The two statistics passes run on
// up to eight meshes at a time (see maskedSums); the results are those of one mesh at a time.
void measurePlainMeshRow(const ImageF& image, int bw, int bh, int nx, int ny, int j, float* level,
                         float* rms, unsigned char* bad) {
  const std::int64_t w = image.width();
  const std::int64_t h = image.height();
  const std::int64_t y0 = static_cast<std::int64_t>(j) * bh;
  const int rows = (j == ny - 1 && h % bh) ? static_cast<int>(h % bh) : bh;
  const StatRows stat(w, bh, rows);
  const float* statBase = image.data() + (y0 + stat.first) * w;
  const std::int64_t statStride = static_cast<std::int64_t>(stat.step) * w;
  auto meshWidth = [&](int i) { return (i == nx - 1 && w % bw) ? static_cast<int>(w % bw) : bw; };

  // Runs kernel<K>(i) over groups of K = 8 meshes of full width (enough independent chains to
  // hide the latency of the additions), then 4, then mesh by mesh.
  const int fullMeshes = w % bw ? nx - 1 : nx;
  auto forMeshGroups = [&](auto&& kernel) {
    int i = 0;
    for (; i + 8 <= fullMeshes; i += 8) kernel(std::integral_constant<int, 8>{}, i, bw);
    for (; i + 4 <= fullMeshes; i += 4) kernel(std::integral_constant<int, 4>{}, i, bw);
    for (; i < nx; ++i) kernel(std::integral_constant<int, 1>{}, i, meshWidth(i));
  };

  const std::size_t n = static_cast<std::size_t>(nx);
  std::vector<double> sum(n), sumSq(n);
  std::vector<std::int64_t> npix(n);
  std::vector<float> lcut(n), hcut(n);
  // Pass 1: plain mean and sigma of the valid pixels.
  forMeshGroups([&](auto group, int i, int mw) {
    maskedSums<decltype(group)::value>(
        statBase + static_cast<std::int64_t>(i) * bw, statStride, stat.count, mw, bw,
        [](int, float v) {
          // detail::isValidPixel as two float comparisons that vectorise (NaN fails both).
          return (v > kBlankFloat) & (v < std::numeric_limits<float>::infinity());
        },
        &sum[i], &sumSq[i], &npix[i]);
  });
  // Pass 2: the same within mean +- 2 sigma (cuts rounded to float, as SExtractor does). A bad
  // mesh gets cuts too (possibly NaN, which keep nothing); its sums are not used.
  std::vector<unsigned char> isBad(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int mw = meshWidth(static_cast<int>(i));
    isBad[i] = static_cast<float>(npix[i]) <
               static_cast<float>(static_cast<double>(mw) * stat.count * kMinGoodFraction);
    const double mean = sum[i] / static_cast<double>(npix[i]);
    const double v2 = sumSq[i] / static_cast<double>(npix[i]) - mean * mean;
    const double sigma = v2 > 0.0 ? std::sqrt(v2) : 0.0;
    lcut[i] = static_cast<float>(mean - 2.0 * sigma);
    hcut[i] = static_cast<float>(mean + 2.0 * sigma);
  }
  forMeshGroups([&](auto group, int i, int mw) {
    const float* lc = &lcut[i];
    const float* hc = &hcut[i];
    maskedSums<decltype(group)::value>(
        statBase + static_cast<std::int64_t>(i) * bw, statStride, stat.count, mw, bw,
        [lc, hc](int k, float v) { return (v <= hc[k]) & (v >= lc[k]); }, &sum[i], &sumSq[i],
        &npix[i]);
  });

  // Pass 3: histograms of every pixel of the mesh (not only the sampled rows), with a spare bin
  // at each end for the pixels outside.
  std::vector<std::int64_t> histo;
  std::vector<std::uint64_t> scratch;
  std::vector<int> index(static_cast<std::size_t>(bw));
  for (int i = 0; i < nx; ++i) {
    const std::size_t k = static_cast<std::size_t>(j) * nx + i;
    if (isBad[i] || npix[i] == 0) {
      bad[k] = 1;
      level[k] = rms[k] = 0.0f;
      continue;
    }
    MeshStat m;
    finishStat(m, sum[i], sumSq[i], npix[i]);
    histo.assign(static_cast<std::size_t>(m.nlevels) + 2, 0);
    const Binner bin(m);
    const int mw = meshWidth(i);
    for (int r = 0; r < rows; ++r) {
      const float* p = image.data() + (y0 + r) * w + static_cast<std::int64_t>(i) * bw;
      for (int x = 0; x < mw; ++x) index[x] = bin.shiftedIndex(p[x]);
      for (int x = 0; x < mw; ++x) ++histo[static_cast<std::size_t>(index[x])];
    }
    bad[k] = 0;
    histogramMode(m, std::span<const std::int64_t>(histo).subspan(1, m.nlevels), scratch, level[k],
                  rms[k]);
  }
}

// The mesh statistics of measureMeshRow with a weight map: pixels whose variance reaches the
// threshold are left out, and the variance map gets its own statistics and histogram.
void measureWeightedMeshRow(const ImageF& image, const WeightRow& wr, int bw, int bh, int nx,
                            int ny, int j, float* level, float* rms, unsigned char* bad) {
  const std::int64_t w = image.width();
  const std::int64_t h = image.height();
  const std::int64_t y0 = static_cast<std::int64_t>(j) * bh;
  const int rows = (j == ny - 1 && h % bh) ? static_cast<int>(h % bh) : bh;
  const float* wmap = wr.map->data();
  const WeightMapType wtype = wr.type;
  const float wthresh = wr.threshold;
  const StatRows stat(w, bh, rows);
  auto statRow = [&](int r) {
    return (y0 + stat.first + static_cast<std::int64_t>(r) * stat.step) * w;
  };

  std::vector<std::int64_t> histo, whisto;
  std::vector<std::uint64_t> scratch;
  for (int i = 0; i < nx; ++i) {
    const std::int64_t x0 = static_cast<std::int64_t>(i) * bw;
    const int mw = (i == nx - 1 && w % bw) ? static_cast<int>(w % bw) : bw;
    const std::size_t k = static_cast<std::size_t>(j) * nx + i;
    MeshStat m, wm;

    // Pass 1: plain mean and sigma of the valid pixels (double sums in SExtractor's order).
    double sum = 0.0, sumSq = 0.0, wsum = 0.0, wsumSq = 0.0;
    std::int64_t npix = 0;
    for (int r = 0; r < stat.count; ++r) {
      const std::int64_t o = statRow(r) + x0;
      const float* p = image.data() + o;
      const float* q = wmap + o;
      for (int x = 0; x < mw; ++x) {
        const float v = p[x];
        const double wv = toVariance(wtype, q[x], 1.0f);
        if (wv < wthresh && detail::isValidPixel(v)) {
          wsum += wv;
          wsumSq += wv * wv;
          const double d = v;
          sum += d;
          sumSq += d * d;
          ++npix;
        }
      }
    }
    bool isBad = static_cast<float>(npix) <
                 static_cast<float>(static_cast<double>(mw) * stat.count * kMinGoodFraction);
    if (!isBad) {
      // Pass 2: the same within mean +- 2 sigma (cuts rounded to float, as SExtractor does);
      // the variance map is clipped the same way, among the pixels the image pass keeps.
      double mean = sum / static_cast<double>(npix);
      double v2 = sumSq / static_cast<double>(npix) - mean * mean;
      double sigma = v2 > 0.0 ? std::sqrt(v2) : 0.0;
      const float lcut = static_cast<float>(mean - 2.0 * sigma);
      const float hcut = static_cast<float>(mean + 2.0 * sigma);
      const double wmean = wsum / static_cast<double>(npix);
      const double wv2 = wsumSq / static_cast<double>(npix) - wmean * wmean;
      const double wsigma = wv2 > 0.0 ? std::sqrt(wv2) : 0.0;
      const float wlcut = static_cast<float>(wmean - 2.0 * wsigma);
      const float whcut = static_cast<float>(wmean + 2.0 * wsigma);
      sum = sumSq = wsum = wsumSq = 0.0;
      npix = 0;
      std::int64_t wnpix = 0;
      for (int r = 0; r < stat.count; ++r) {
        const std::int64_t o = statRow(r) + x0;
        const float* p = image.data() + o;
        const float* q = wmap + o;
        for (int x = 0; x < mw; ++x) {
          const float v = p[x];
          const float wv = toVariance(wtype, q[x], 1.0f);
          if (wv < wthresh && v <= hcut && v >= lcut) {
            const double d = v;
            sum += d;
            sumSq += d * d;
            ++npix;
            if (wv <= whcut && wv >= wlcut) {
              const double dw = wv;
              wsum += dw;
              wsumSq += dw * dw;
              ++wnpix;
            }
          }
        }
      }
      if (npix == 0) {
        isBad = true;
      } else {
        finishStat(m, sum, sumSq, npix);
        // An empty variance selection gives NaN statistics, as in SExtractor.
        finishStat(wm, wsum, wsumSq, wnpix);
      }
    }

    if (isBad) {
      bad[k] = 1;
      level[k] = rms[k] = 0.0f;
      wr.level[k] = wr.rms[k] = 0.0f;
      continue;
    }
    // Pass 3: histograms of every pixel of the mesh (not only the sampled rows).
    histo.assign(static_cast<std::size_t>(m.nlevels), 0);
    whisto.assign(static_cast<std::size_t>(std::max(wm.nlevels, 1)), 0);
    const Binner bin(m);
    const Binner wbin(wm);
    for (int r = 0; r < rows; ++r) {
      const std::int64_t o = (y0 + r) * w + x0;
      const float* p = image.data() + o;
      const float* q = wmap + o;
      for (int x = 0; x < mw; ++x) {
        const int b = bin(p[x]);
        const float wv = toVariance(wtype, q[x], 1.0f);
        if (wv < wthresh && b >= 0) {
          ++histo[static_cast<std::size_t>(b)];
          const int wb = wbin(wv);
          if (wb >= 0) ++whisto[static_cast<std::size_t>(wb)];
        }
      }
    }
    bad[k] = 0;
    histogramMode(m, histo, scratch, level[k], rms[k]);
    histogramMode(wm, whisto, scratch, wr.level[k], wr.rms[k]);
  }
}

// Everything about one row of meshes: statistics, histogram, mode; the same for the variance
// map when `wr` is given (SExtractor's backstat / backhisto / backguess).
void measureMeshRow(const ImageF& image, const WeightRow* wr, int bw, int bh, int nx, int ny, int j,
                    float* level, float* rms, unsigned char* bad) {
  if (wr)
    measureWeightedMeshRow(image, *wr, bw, bh, nx, ny, j, level, rms, bad);
  else
    measurePlainMeshRow(image, bw, bh, nx, ny, j, level, rms, bad);
}

// Natural-spline second derivatives along y for every mesh column, with SExtractor's scaling
// (each back-substituted value divided by 6; the interpolation formulas expect exactly this).
std::vector<float> splineAlongY(const ImageF& grid) {
  const int nx = static_cast<int>(grid.width());
  const int ny = static_cast<int>(grid.height());
  std::vector<float> d2(static_cast<std::size_t>(nx) * ny, 0.0f);
  if (ny < 2) return d2;
  std::vector<float> u(static_cast<std::size_t>(ny), 0.0f);
  for (int x = 0; x < nx; ++x) {
    auto m = [&](int y) { return grid(x, y); };
    float* d = d2.data() + x;
    auto at = [&](int y) -> float& { return d[static_cast<std::size_t>(y) * nx]; };
    at(0) = 0.0f;
    u[0] = 0.0f;
    for (int y = 1; y < ny - 1; ++y) {
      float t = -1.0f / (at(y - 1) + 4.0f);
      at(y) = t;
      t *= u[y - 1] - 6.0f * (m(y + 1) + m(y - 1) - 2.0f * m(y));
      u[y] = t;
    }
    at(ny - 1) = 0.0f;
    for (int y = ny - 2; y >= 1; --y) at(y) = static_cast<float>((at(y) * at(y + 1) + u[y]) / 6.0);
  }
  return d2;
}

// SExtractor's filterback: bad meshes take the mean of their nearest good meshes (all those at
// the minimal distance, summed in raster order; 0 and 1 when there is no good mesh), then a
// median filter, its window shrunk symmetrically near the edges of the grid, applied where the
// median differs from the mesh value by at least the threshold.
void filterMeshGrid(const ImageF& level, ImageF rms, const std::vector<unsigned char>& bad,
                    std::size_t goodCount, const MeshBackgroundSettings& s, ImageF& outLevel,
                    ImageF& outRms) {
  const int nx = static_cast<int>(level.width()), ny = static_cast<int>(level.height());
  // The search box for the nearest good meshes grows until it must contain them all.
  ImageF filled = level;
  for (int py = 0; py < ny; ++py) {
    for (int px = 0; px < nx; ++px) {
      const std::size_t k = static_cast<std::size_t>(py) * nx + px;
      if (!bad[k]) continue;
      if (goodCount == 0) {
        filled[k] = 0.0f;
        rms[k] = 1.0f;
        continue;
      }
      int ring = 1;
      for (;; ++ring) {
        bool found = false;
        for (int y = std::max(0, py - ring); y <= std::min(ny - 1, py + ring) && !found; ++y)
          for (int x = std::max(0, px - ring); x <= std::min(nx - 1, px + ring); ++x)
            if (!bad[static_cast<std::size_t>(y) * nx + x]) {
              found = true;
              break;
            }
        if (found) break;
      }
      // The nearest good mesh is within Chebyshev distance `ring`, so Euclidean <= ring*sqrt(2).
      const int reach = static_cast<int>(std::ceil(ring * std::sqrt(2.0))) + 1;
      float d2min = 1e30f, val = 0.0f, sval = 0.0f;
      int nmin = 0;
      for (int y = std::max(0, py - reach); y <= std::min(ny - 1, py + reach); ++y) {
        for (int x = std::max(0, px - reach); x <= std::min(nx - 1, px + reach); ++x) {
          const std::size_t q = static_cast<std::size_t>(y) * nx + x;
          if (bad[q]) continue;
          const float d2 = static_cast<float>((x - px) * (x - px) + (y - py) * (y - py));
          if (d2 < d2min) {
            val = level[q];
            sval = rms[q];
            nmin = 1;
            d2min = d2;
          } else if (d2 == d2min) {
            val += level[q];
            sval += rms[q];
            ++nmin;
          }
        }
      }
      filled[k] = val / static_cast<float>(nmin);
      rms[k] = sval / static_cast<float>(nmin);
    }
  }

  const int halfX = (nx > 1 ? s.filterWidth : 1) / 2;
  const int halfY = (ny > 1 ? s.filterHeight : 1) / 2;
  const float thresholdAdu = static_cast<float>(s.filterThresholdAdu);
  outLevel = ImageF(nx, ny);
  outRms = ImageF(nx, ny);
  std::vector<float> wl, ws;
  for (int py = 0; py < ny; ++py) {
    const int hy = std::min({halfY, py, ny - 1 - py});
    for (int px = 0; px < nx; ++px) {
      const int hx = std::min({halfX, px, nx - 1 - px});
      wl.clear();
      ws.clear();
      for (int y = py - hy; y <= py + hy; ++y)
        for (int x = px - hx; x <= px + hx; ++x) {
          wl.push_back(filled(x, y));
          ws.push_back(rms(x, y));
        }
      const float med = detail::medianInPlace(wl);
      if (std::fabs(med - filled(px, py)) >= thresholdAdu) {
        outLevel(px, py) = med;
        outRms(px, py) = detail::medianInPlace(ws);
      } else {
        outLevel(px, py) = filled(px, py);
        outRms(px, py) = rms(px, py);
      }
    }
  }
}

}  // namespace

namespace {

void checkMeshInputs(const ImageF& image, const MeshBackgroundSettings& s, const WeightMap& weights,
                     const std::string& name) {
  if (s.meshWidth < 1 || s.meshHeight < 1)
    throw ConfigError("BACK_SIZE: mesh size must be at least 1 pixel, got " +
                      std::to_string(s.meshWidth) + "x" + std::to_string(s.meshHeight));
  if (s.filterWidth < 1 || s.filterHeight < 1)
    throw ConfigError("BACK_FILTERSIZE: filter size must be at least 1 mesh, got " +
                      std::to_string(s.filterWidth) + "x" + std::to_string(s.filterHeight));
  if (image.width() < 1 || image.height() < 1)
    throw IoError(name + ": empty image, cannot estimate the background");
  if (image.width() > std::numeric_limits<std::int32_t>::max() ||
      image.height() > std::numeric_limits<std::int32_t>::max())
    throw IoError(name + ": image too large for the background mesh");
  if (weights.pixels &&
      (weights.pixels->width() != image.width() || weights.pixels->height() != image.height()))
    throw IoError(weights.name + ": weight map is " + std::to_string(weights.pixels->width()) +
                  "x" + std::to_string(weights.pixels->height()) + " but " + name + " is " +
                  std::to_string(image.width()) + "x" + std::to_string(image.height()));
}

}  // namespace

MeshBackground MeshBackground::estimate(const ImageF& image, const MeshBackgroundSettings& s,
                                        std::string_view imageName) {
  return estimate(image, s, WeightMap{}, imageName);
}

MeshBackground MeshBackground::estimate(const ImageF& image, const MeshBackgroundSettings& s,
                                        const WeightMap& weights, std::string_view imageName) {
  const std::string name(imageName);
  checkMeshInputs(image, s, weights, name);

  MeshBackground b;
  b.width_ = image.width();
  b.height_ = image.height();
  b.meshWidth_ = static_cast<int>(std::min<std::int64_t>(s.meshWidth, b.width_));
  b.meshHeight_ = static_cast<int>(std::min<std::int64_t>(s.meshHeight, b.height_));
  b.nx_ = static_cast<int>((b.width_ - 1) / b.meshWidth_ + 1);
  b.ny_ = static_cast<int>((b.height_ - 1) / b.meshHeight_ + 1);
  b.threadCount_ = resolveThreads(s.threadCount);
  const int nx = b.nx_, ny = b.ny_;
  const std::size_t nb = static_cast<std::size_t>(nx) * ny;

  // Mesh statistics, one mesh row per task; every mesh is independent, so the result does not
  // depend on how rows are shared between threads.
  ImageF level(nx, ny), rms(nx, ny), wlevel, wrms;
  std::vector<unsigned char> bad(nb, 0);
  WeightRow wr;
  b.hasWeights_ = weights.pixels != nullptr;
  if (b.hasWeights_) {
    // The threshold goes through the same conversion as the pixels (as a float, scale 1).
    const float given = static_cast<float>(
        weights.threshold.value_or(weights.type == WeightMapType::Weight ? 0.0 : 1e30));
    b.weightType_ = weights.type;
    b.varianceThreshold_ = toVariance(weights.type, given, 1.0f);
    wlevel = ImageF(nx, ny);
    wrms = ImageF(nx, ny);
    wr.map = weights.pixels;
    wr.type = weights.type;
    wr.threshold = b.varianceThreshold_;
    wr.level = wlevel.data();
    wr.rms = wrms.data();
  }
  parallelFor(ny, std::min(b.threadCount_, ny), [&](std::int64_t j) {
    measureMeshRow(image, b.hasWeights_ ? &wr : nullptr, b.meshWidth_, b.meshHeight_, nx, ny,
                   static_cast<int>(j), level.data(), rms.data(), bad.data());
  });

  const std::size_t goodCount =
      nb - static_cast<std::size_t>(std::count(bad.begin(), bad.end(), 1));
  if (goodCount == 0) {
    const bool anyValid = detail::countValid(image, b.threadCount_) > 0;
    if (!anyValid)
      throw IoError(name +
                    ": no valid pixels (all NaN, infinite or blank), cannot estimate the "
                    "background");
    b.warnings_.push_back(name +
                          ": no background mesh has half of its pixels valid; background "
                          "set to 0 and its rms to 1");
  }

  filterMeshGrid(level, rms, bad, goodCount, s, b.meshLevel_, b.meshRms_);

  // Global level and noise: medians of the grids.
  std::vector<float> all(b.meshLevel_.data(), b.meshLevel_.data() + b.meshLevel_.size());
  b.globalLevelAdu_ = detail::medianInPlace(all);
  const float sigma = b.medianMeshSigma(name);
  b.globalSigmaAdu_ = sigma;
  if (b.hasWeights_) b.scaleWeights(wlevel, wrms, bad, goodCount, s, weights, sigma);

  b.levelD2y_ = splineAlongY(b.meshLevel_);
  b.rmsD2y_ = splineAlongY(b.meshRms_);
  b.buildColumnWalk();
  return b;
}

float MeshBackground::medianMeshSigma(const std::string& name) {
  // A zero median rms falls back on the median of the positive meshes, and to 1 (with a
  // warning) when no mesh has any noise.
  std::vector<float> all(meshRms_.data(), meshRms_.data() + meshRms_.size());
  float sigma = detail::medianInPlace(all);  // `all` is sorted now
  if (sigma <= 0.0f) {
    const auto firstPositive = std::upper_bound(all.begin(), all.end(), 0.0f);
    if (firstPositive != all.end() && firstPositive != all.begin()) {
      std::vector<float> positive(firstPositive, all.end());
      sigma = detail::medianInPlace(positive);
    } else {
      warnings_.push_back(name +
                          ": image contains mainly constant data; background noise "
                          "sigma set to 1");
      sigma = 1.0f;
    }
  }
  return sigma;
}

void MeshBackground::scaleWeights(const ImageF& wlevel, const ImageF& wrms,
                                  const std::vector<unsigned char>& bad, std::size_t goodCount,
                                  const MeshBackgroundSettings& s, const WeightMap& weights,
                                  float sigma) {
  ImageF filteredVarianceRms;
  filterMeshGrid(wlevel, wrms, bad, goodCount, s, meshVariance_, filteredVarianceRms);
  if (weights.type == WeightMapType::Rms) return;
  // Weight scale: median over meshes of rms / sqrt(variance mode), positive ratios only.
  std::vector<float> ratios;
  for (std::int64_t k = 0; k < meshVariance_.size(); ++k) {
    const float v = meshVariance_[k];
    if (!(v > 0.0f)) continue;
    const float r = static_cast<float>(meshRms_[k] / std::sqrt(static_cast<double>(v)));
    if (r > 0.0f) ratios.push_back(r);
  }
  float scale = 1.0f;
  if (ratios.empty())
    warnings_.push_back(weights.name + ": null or negative global weighting factor; set to 1");
  else
    scale = detail::medianInPlace(ratios);
  if (weights.rescale) {
    weightScale_ = scale;
  } else {
    globalSigmaAdu_ = static_cast<float>(sigma / scale);
  }
}

void MeshBackground::buildColumnWalk() {
  // SExtractor steps dx by 1/meshWidth in float from the first pixel and resets it at the first
  // pixel past each mesh centre; replaying that walk once gives the exact per-column values,
  // the same for every row.
  const int nx = nx_;
  const std::int64_t w = width_;
  xDx_.assign(static_cast<std::size_t>(w), 0.0f);
  xCdx_.assign(static_cast<std::size_t>(w), 0.0f);
  xDx3_.assign(static_cast<std::size_t>(w), 0.0f);
  xCdx3_.assign(static_cast<std::size_t>(w), 0.0f);
  if (nx > 1 && meshWidth_ > 1) {
    const int bw = meshWidth_;
    const float step = static_cast<float>(1.0 / bw);
    const int change = bw / 2;
    float dx = (step - 1.0f) / 2.0f;
    const float dxAfterNode = static_cast<float>((bw + 1) % 2) * step / 2.0f;
    int node = 0, segment = 0, i = 0;
    for (std::int64_t x = 0; x < w; ++x, ++i, dx += step) {
      if (i == change && segment > 0 && segment < nx - 1) {
        ++node;
        dx = dxAfterNode;
      }
      const float cdx = 1.0f - dx;
      if (xRuns_.empty() || xRuns_.back().node != node) xRuns_.push_back({x, x, node});
      xRuns_.back().end = x + 1;
      xDx_[x] = dx;
      xCdx_[x] = cdx;
      xDx3_[x] = dx * dx - 1.0f;
      xCdx3_[x] = cdx * cdx - 1.0f;
      if (i == bw) {
        ++segment;
        i = 0;
      }
    }
  }
}

void MeshBackground::interpolateRow(const ImageF& grid, const std::vector<float>& d2y,
                                    std::int64_t y, float* out, bool subtract) const {
  const int nx = nx_, ny = ny_;
  // Nodes of this row: spline along y through each mesh column (float, SExtractor's order).
  // The buffers are kept per thread: rows are interpolated one by one, often by several threads.
  thread_local std::vector<float> buffers;
  buffers.assign(3 * static_cast<std::size_t>(nx), 0.0f);
  float* node = buffers.data();
  float* dnode = node + nx;
  float* u = dnode + nx;
  if (ny > 1) {
    float dy = static_cast<float>(static_cast<float>(y) / static_cast<float>(meshHeight_) - 0.5);
    int yl = static_cast<int>(dy);
    dy -= static_cast<float>(yl);
    if (yl < 0) {
      yl = 0;
      dy -= 1.0f;
    } else if (yl >= ny - 1) {
      yl = ny - 2;
      dy += 1.0f;
    }
    const float cdy = 1.0f - dy;
    const float dy3 = dy * dy * dy - dy;
    const float cdy3 = cdy * cdy * cdy - cdy;
    const float* lo = grid.data() + static_cast<std::size_t>(yl) * nx;
    const float* hi = lo + nx;
    const float* dlo = d2y.data() + static_cast<std::size_t>(yl) * nx;
    const float* dhi = dlo + nx;
    for (int x = 0; x < nx; ++x) node[x] = cdy * lo[x] + dy * hi[x] + cdy3 * dlo[x] + dy3 * dhi[x];
    // Second derivatives along x through the nodes.
    if (nx > 1) {
      for (int k = 1; k < nx - 1; ++k) {
        float t = -1.0f / (dnode[k - 1] + 4.0f);
        dnode[k] = t;
        t *= u[k - 1] - 6.0f * (node[k + 1] + node[k - 1] - 2.0f * node[k]);
        u[k] = t;
      }
      dnode[nx - 1] = 0.0f;
      for (int k = nx - 2; k >= 1; --k)
        dnode[k] = static_cast<float>((dnode[k] * dnode[k + 1] + u[k]) / 6.0);
    }
  } else {
    // One mesh row: SExtractor uses the grid itself with zero second derivatives, which makes
    // the interpolation along x linear.
    std::copy(grid.data(), grid.data() + nx, node);
  }

  const std::int64_t w = width_;
  // The same arithmetic for both uses: the row value is computed in float, then stored or
  // subtracted (so that subtracting gives exactly row - levelRow).
  auto emit = [out, subtract](std::int64_t x, float value) {
    if (subtract)
      out[x] -= value;
    else
      out[x] = value;
  };
  if (nx == 1) {
    for (std::int64_t x = 0; x < w; ++x) emit(x, node[0]);
    return;
  }
  if (meshWidth_ == 1) {  // one node per column
    for (std::int64_t x = 0; x < w; ++x) emit(x, node[x]);
    return;
  }
  // Columns sharing a node interval form contiguous runs; the inner loops vectorise.
  const float* dx = xDx_.data();
  const float* cdx = xCdx_.data();
  const float* dx3 = xDx3_.data();
  const float* cdx3 = xCdx3_.data();
  for (const XRun& run : xRuns_) {
    const int k = run.node;
    const float blo = node[k], bhi = node[k + 1], dlo = dnode[k], dhi = dnode[k + 1];
    if (subtract) {
      for (std::int64_t i = run.begin; i < run.end; ++i)
        out[i] -= cdx[i] * (blo + cdx3[i] * dlo) + dx[i] * (bhi + dx3[i] * dhi);
    } else {
      for (std::int64_t i = run.begin; i < run.end; ++i)
        out[i] = cdx[i] * (blo + cdx3[i] * dlo) + dx[i] * (bhi + dx3[i] * dhi);
    }
  }
}

float MeshBackground::pixelVariance(float weightPixel) const {
  const float scale = static_cast<float>(weightScale_);
  return toVariance(weightType_, weightPixel, scale * scale);
}

void MeshBackground::levelRow(std::int64_t y, float* out) const {
  interpolateRow(meshLevel_, levelD2y_, y, out, false);
}

void MeshBackground::rmsRow(std::int64_t y, float* out) const {
  interpolateRow(meshRms_, rmsD2y_, y, out, false);
}

void MeshBackground::subtractRow(std::int64_t y, float* row) const {
  interpolateRow(meshLevel_, levelD2y_, y, row, true);
}

void MeshBackground::fillImage(ImageF& out, bool isLevel) const {
  out = ImageF(width_, height_, UninitializedPixels{});  // every row is written below
  parallelBlocks(height_, threadCount_, [&](std::int64_t y0, std::int64_t y1) {
    for (std::int64_t y = y0; y < y1; ++y) {
      float* row = out.data() + y * width_;
      if (isLevel)
        levelRow(y, row);
      else
        rmsRow(y, row);
    }
  });
}

ImageF MeshBackground::levelImage() const {
  ImageF out;
  fillImage(out, true);
  return out;
}

ImageF MeshBackground::rmsImage() const {
  ImageF out;
  fillImage(out, false);
  return out;
}

}  // namespace octarc
