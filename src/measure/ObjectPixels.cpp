#include "octarc/measure/ObjectPixels.h"

#include <cmath>

namespace octarc {

void ObjectPixels::gather(const Segment& segment, const MeasureContext& context) {
  const std::size_t n = segment.pixels.size();
  x.resize(n);
  y.resize(n);
  value.resize(n);
  separateDetection = context.detection != nullptr && context.detection != context.measurement;
  detection.resize(separateDetection ? n : 0);
  variance.resize(context.variance ? n : 0);
  valuesFinite = true;
  if (n == 0) return;
  const ImageF& measured = *context.measurement;
  const ImageF& detected = context.detection ? *context.detection : measured;
  const std::int64_t width = measured.width();
  // Footprints come in raster order: one division per image row, not one per pixel.
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
    if (!std::isfinite(v)) valuesFinite = false;
  }
  if (separateDetection) {
    for (std::size_t i = 0; i < n; ++i) detection[i] = detected[segment.pixels[i]];
  }
  if (context.variance) {
    const ImageF& var = *context.variance;
    for (std::size_t i = 0; i < n; ++i) variance[i] = var[segment.pixels[i]];
  }
}

}  // namespace octarc
