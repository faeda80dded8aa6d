// One object at one threshold: a set of pixels that measurements read. A value type of every
// stage after detection (measurements, catalogs, simulations, the search).
#pragma once

#include <cstdint>
#include <vector>

namespace octarc {

// The most detection thresholds a run may have (DETECT_NLEVELS, a grid's NTHRESH, a simulation's
// OCTNLEV): the detector counts the levels a pixel is above in a byte.
inline constexpr int kMaxThresholdLevels = 255;

// One detection threshold of a (possibly single-level) run.
struct ThresholdLevel {
  int level = 1;                      // THRESH_LEVEL, 1 = lowest
  double thresholdAdu = 0.0;          // detection threshold in ADU (SEXTHLD / THRESHOLD column)
  double analysisThresholdAdu = 0.0;  // analysis threshold in ADU (ISOAREA_IMAGE), SEXATHLD
  double thresholdSigma = 0.0;  // the same in units of the global noise sigma (NaN if unknown)
};

// Pixels x0..x1 (inclusive, 0-based) of image row y.
struct PixelRun {
  std::int32_t y = 0;
  std::int32_t x0 = 0;
  std::int32_t x1 = -1;
  std::int64_t length() const { return std::int64_t(x1) - x0 + 1; }
};

// The footprint is held one of two ways: as pixel indices, or (from the detector, when asked,
// which saves writing and reading an index per pixel) as runs in raster order with `pixels`
// empty. Code that reads footprints handles both, through the helpers below.
struct Segment {
  std::int32_t number = 0;        // NUMBER: SExtractor's object number within its level (>= 1)
  int level = 1;                  // THRESH_LEVEL of this object (index into the level list + 1)
  std::int32_t parentNumber = 0;  // NUMBER of the containing object one level below; 0 at level 1
  std::vector<std::int64_t> pixels;  // linear indices y * width + x (0-based) of the footprint
  std::vector<PixelRun> runs;        // or the footprint as runs (then `pixels` is empty)

  std::int64_t pixelCount() const {
    if (!pixels.empty() || runs.empty()) return std::int64_t(pixels.size());
    std::int64_t n = 0;
    for (const PixelRun& r : runs) n += r.length();
    return n;
  }
  // Calls f(linear index) for every footprint pixel, in the stored order.
  template <typename F>
  void forEachIndex(std::int64_t width, F&& f) const {
    if (!pixels.empty()) {
      for (const std::int64_t p : pixels) f(p);
      return;
    }
    for (const PixelRun& r : runs) {
      const std::int64_t first = std::int64_t(r.y) * width;
      for (std::int64_t x = r.x0; x <= r.x1; ++x) f(first + x);
    }
  }
};

}  // namespace octarc
