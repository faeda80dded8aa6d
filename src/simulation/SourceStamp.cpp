#include "octarc/simulation/SourceStamp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace octarc::simulation {

const char* galaxyTypeName(GalaxyType type) {
  switch (type) {
    case GalaxyType::Elliptical:
      return "elliptical";
    case GalaxyType::Spiral:
      return "spiral";
    case GalaxyType::Irregular:
      return "irregular";
  }
  return "unknown";
}

double totalFlux(const SourceStamp& stamp) {
  double sum = 0.0;
  for (double v : stamp.fluxPerPixel.pixels()) sum += v;
  return sum;
}

double halfLightRadiusArcsec(const SourceStamp& stamp) {
  const ImageD& img = stamp.fluxPerPixel;
  const double total = totalFlux(stamp);
  if (!(total > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  // Flux centroid, accumulated about the stamp centre (local origin) for precision.
  const double cx = 0.5 * (img.width() - 1);
  const double cy = 0.5 * (img.height() - 1);
  double sx = 0.0;
  double sy = 0.0;
  for (std::int64_t y = 0; y < img.height(); ++y)
    for (std::int64_t x = 0; x < img.width(); ++x) {
      sx += img(x, y) * (x - cx);
      sy += img(x, y) * (y - cy);
    }
  const double mx = cx + sx / total;
  const double my = cy + sy / total;
  std::vector<std::pair<double, double>> byRadius;  // (radius in pixels, flux)
  byRadius.reserve(static_cast<std::size_t>(img.size()));
  for (std::int64_t y = 0; y < img.height(); ++y)
    for (std::int64_t x = 0; x < img.width(); ++x)
      byRadius.emplace_back(std::hypot(x - mx, y - my), img(x, y));
  std::sort(byRadius.begin(), byRadius.end());
  double cumulative = 0.0;
  double previousRadius = 0.0;
  double previousCumulative = 0.0;
  for (const auto& [r, f] : byRadius) {
    cumulative += f;
    if (cumulative >= 0.5 * total) {
      const double t = f > 0.0 ? (0.5 * total - previousCumulative) / f : 1.0;
      return (previousRadius + t * (r - previousRadius)) * stamp.pixelScaleArcsec;
    }
    previousRadius = r;
    previousCumulative = cumulative;
  }
  return previousRadius * stamp.pixelScaleArcsec;
}

}  // namespace octarc::simulation
