#include "octarc/simulation/GalaxyCutout.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "octarc/core/Error.h"

namespace octarc::simulation {

const char* cutoutVerdictName(CutoutVerdict verdict) {
  switch (verdict) {
    case CutoutVerdict::Kept:
      return "kept";
    case CutoutVerdict::TouchesBorder:
      return "touching the border or blank pixels";
    case CutoutVerdict::TooSmall:
      return "too small";
    case CutoutVerdict::Saturated:
      return "saturated";
    case CutoutVerdict::NoFlux:
      return "without positive flux";
  }
  return "?";
}

namespace {

// True if a footprint pixel has a blank (NaN or infinite) neighbour: the edge of the valid data
// inside the image (mosaic borders, masked areas) truncates the galaxy as the image border does.
// The footprint must not touch the image border (neighbours are not bounds-checked).
bool touchesBlankPixels(const ImageF& image, const Segment& object) {
  const std::int64_t w = image.width();
  for (std::int64_t p : object.pixels) {
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        if (!std::isfinite(image[p + dy * w + dx])) return true;
      }
  }
  return false;
}

}  // namespace

GalaxyCutout cutGalaxy(const ImageF& backgroundSubtracted, const Segment& object,
                       const std::vector<std::int64_t>& saturatedPixels,
                       const CutoutSettings& settings) {
  if (settings.minAreaPixels < 1)
    throw ConfigError("galaxy cutout: the minimum area must be at least 1 pixel, got " +
                      std::to_string(settings.minAreaPixels));
  if (settings.marginPixels < 0)
    throw ConfigError("galaxy cutout: the margin must not be negative, got " +
                      std::to_string(settings.marginPixels));
  const std::int64_t width = backgroundSubtracted.width();
  const std::int64_t height = backgroundSubtracted.height();

  GalaxyCutout out;
  out.areaPixels = static_cast<std::int64_t>(object.pixels.size());
  std::int64_t xMin = width, xMax = -1, yMin = height, yMax = -1;
  bool saturated = false;
  // Centroid about the first pixel (local origin), so the sums keep their precision.
  const std::int64_t x0 = object.pixels.empty() ? 0 : object.pixels.front() % width;
  const std::int64_t y0 = object.pixels.empty() ? 0 : object.pixels.front() / width;
  double sum = 0.0, sumX = 0.0, sumY = 0.0;
  for (std::int64_t p : object.pixels) {
    if (p < 0 || p >= backgroundSubtracted.size())
      throw ConfigError("object " + std::to_string(object.number) + ": pixel index " +
                        std::to_string(p) + " lies outside the " + std::to_string(width) + "x" +
                        std::to_string(height) + " image");
    const std::int64_t x = p % width;
    const std::int64_t y = p / width;
    xMin = std::min(xMin, x);
    xMax = std::max(xMax, x);
    yMin = std::min(yMin, y);
    yMax = std::max(yMax, y);
    if (std::binary_search(saturatedPixels.begin(), saturatedPixels.end(), p)) saturated = true;
    const double v = backgroundSubtracted[p];
    sum += v;
    sumX += v * double(x - x0);
    sumY += v * double(y - y0);
  }
  out.fluxAdu = sum;
  if (xMin == 0 || yMin == 0 || xMax == width - 1 || yMax == height - 1 ||
      touchesBlankPixels(backgroundSubtracted, object)) {
    out.verdict = CutoutVerdict::TouchesBorder;
    return out;
  }
  if (out.areaPixels < settings.minAreaPixels) {
    out.verdict = CutoutVerdict::TooSmall;
    return out;
  }
  if (saturated) {
    out.verdict = CutoutVerdict::Saturated;
    return out;
  }
  if (!(sum > 0.0)) {
    out.verdict = CutoutVerdict::NoFlux;
    return out;
  }
  out.xCentroidPix = double(x0) + sumX / sum;
  out.yCentroidPix = double(y0) + sumY / sum;
  // Footprint pixels are above a positive threshold, so the centroid lies within the bounding
  // box; the clamp only guards against rounding at its edge.
  const std::int64_t cx = std::clamp<std::int64_t>(std::llround(out.xCentroidPix), xMin, xMax);
  const std::int64_t cy = std::clamp<std::int64_t>(std::llround(out.yCentroidPix), yMin, yMax);
  const std::int64_t halfW = std::max(cx - xMin, xMax - cx) + settings.marginPixels;
  const std::int64_t halfH = std::max(cy - yMin, yMax - cy) + settings.marginPixels;
  out.originX = cx - halfW;
  out.originY = cy - halfH;
  out.stamp = ImageF(2 * halfW + 1, 2 * halfH + 1, 0.0f);
  for (std::int64_t p : object.pixels) {
    out.stamp(p % width - out.originX, p / width - out.originY) = backgroundSubtracted[p];
  }
  return out;
}

}  // namespace octarc::simulation
