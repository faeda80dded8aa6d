#include "octarc/measure/ObjectPixels.h"

#include <cmath>

namespace octarc {

void ObjectPixels::gather(const Segment& segment, const MeasureContext& context) {
  const std::size_t n = std::size_t(segment.pixelCount());
  x.resize(n);
  y.resize(n);
  value.resize(n);
  separateDetection = context.detection != nullptr && context.detection != context.measurement;
  detection.resize(separateDetection ? n : 0);
  variance.resize(context.variance ? n : 0);
  valuesFinite = true;
  if (n == 0) return;
  const ImageF& measured = *context.measurement;
  const ImageF& detected = separateDetection ? *context.detection : measured;
  const std::int64_t width = measured.width();
  bool finite = true;
  if (segment.pixels.empty()) {
    // Runs: rows of contiguous pixels, no index to split.
    std::size_t i = 0;
    for (const PixelRun& r : segment.runs) {
      const std::int64_t first = std::int64_t(r.y) * width + r.x0;
      const std::int64_t length = r.length();
      const float* row = measured.data() + first;
      for (std::int64_t k = 0; k < length; ++k) {
        x[i + std::size_t(k)] = double(r.x0 + k);
        y[i + std::size_t(k)] = double(r.y);
        value[i + std::size_t(k)] = row[k];
        finite &= std::fabs(row[k]) < HUGE_VALF;
      }
      if (separateDetection) {
        for (std::int64_t k = 0; k < length; ++k)
          detection[i + std::size_t(k)] = detected[first + k];
      }
      if (context.variance) {
        const float* var = context.variance->data() + first;
        for (std::int64_t k = 0; k < length; ++k) variance[i + std::size_t(k)] = var[k];
      }
      i += std::size_t(length);
    }
    valuesFinite = finite;
    return;
  }
  // Pixel indices, usually in raster order: one division per image row, not one per pixel.
  std::int64_t rowStart = 0, rowEnd = 0;
  double rowY = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t p = segment.pixels[i];
    if (p < rowStart || p >= rowEnd) {
      const std::int64_t row = p / width;
      rowStart = row * width;
      rowEnd = rowStart + width;
      rowY = double(row);
    }
    x[i] = double(p - rowStart);
    y[i] = rowY;
    const double v = measured[p];
    value[i] = v;
    finite &= std::fabs(v) < HUGE_VAL;
  }
  valuesFinite = finite;
  if (separateDetection) {
    for (std::size_t i = 0; i < n; ++i) detection[i] = detected[segment.pixels[i]];
  }
  if (context.variance) {
    const ImageF& var = *context.variance;
    for (std::size_t i = 0; i < n; ++i) variance[i] = var[segment.pixels[i]];
  }
}

}  // namespace octarc
