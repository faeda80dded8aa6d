#include "octarc/simulation/Morphology.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace octarc::simulation {

namespace {

struct Centroid {
  double x = 0.0;
  double y = 0.0;
};

// Radii (pixels) about c holding each fraction of the total flux, by linear interpolation along
// the pixels sorted by radius.
std::vector<double> radiiHolding(const ImageD& img, Centroid c, double total,
                                 const std::vector<double>& fractions) {
  std::vector<std::pair<double, double>> byRadius;
  byRadius.reserve(std::size_t(img.size()));
  for (std::int64_t y = 0; y < img.height(); ++y)
    for (std::int64_t x = 0; x < img.width(); ++x)
      byRadius.emplace_back(std::hypot(x - c.x, y - c.y), img(x, y));
  std::sort(byRadius.begin(), byRadius.end());
  std::vector<double> radii(fractions.size(), byRadius.back().first);
  std::size_t next = 0;
  double cumulative = 0.0, previousRadius = 0.0, previousCumulative = 0.0;
  for (const auto& [r, f] : byRadius) {
    cumulative += f;
    while (next < fractions.size() && cumulative >= fractions[next] * total) {
      const double t = f > 0.0 ? (fractions[next] * total - previousCumulative) / f : 1.0;
      radii[next++] = previousRadius + t * (r - previousRadius);
    }
    if (next == fractions.size()) break;
    previousRadius = r;
    previousCumulative = cumulative;
  }
  return radii;
}

// Bilinear value at (x, y), zero outside the stamp.
double sampleAt(const ImageD& img, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto x0 = std::int64_t(fx), y0 = std::int64_t(fy);
  const double tx = x - fx, ty = y - fy;
  auto at = [&](std::int64_t xi, std::int64_t yi) {
    return xi < 0 || yi < 0 || xi >= img.width() || yi >= img.height() ? 0.0 : img(xi, yi);
  };
  return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
         ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
}

// Sum |I - I_180| less its expectation from noise alone (two independent Gaussian deviates of
// sigma differ by 2 sigma / sqrt(pi) on average), over the flux in the aperture: sum |I| would
// count the noise too.
double asymmetryAbout(const ImageD& img, Centroid c, double radiusPix, double noiseSigma) {
  double diff = 0.0, flux = 0.0;
  std::int64_t pixels = 0;
  const auto x0 = std::max<std::int64_t>(0, std::int64_t(std::floor(c.x - radiusPix)));
  const auto x1 = std::min<std::int64_t>(img.width() - 1, std::int64_t(std::ceil(c.x + radiusPix)));
  const auto y0 = std::max<std::int64_t>(0, std::int64_t(std::floor(c.y - radiusPix)));
  const auto y1 =
      std::min<std::int64_t>(img.height() - 1, std::int64_t(std::ceil(c.y + radiusPix)));
  for (std::int64_t y = y0; y <= y1; ++y)
    for (std::int64_t x = x0; x <= x1; ++x) {
      if (std::hypot(x - c.x, y - c.y) > radiusPix) continue;
      const double v = img(x, y);
      diff += std::abs(v - sampleAt(img, 2.0 * c.x - double(x), 2.0 * c.y - double(y)));
      flux += v;
      ++pixels;
    }
  if (!(flux > 0.0)) return 0.0;
  const double noiseDiff = double(pixels) * 2.0 * noiseSigma / std::sqrt(std::numbers::pi);
  return std::max(0.0, diff - noiseDiff) / flux;
}

// Noise of the stamp from its outer two-pixel frame (1.4826 x the median absolute deviation):
// cleaned database stamps keep their sky noise there, synthetic ones are zero.
double frameNoiseSigma(const ImageD& img) {
  std::vector<double> frame;
  for (std::int64_t y = 0; y < img.height(); ++y)
    for (std::int64_t x = 0; x < img.width(); ++x)
      if (x < 2 || y < 2 || x >= img.width() - 2 || y >= img.height() - 2)
        frame.push_back(img(x, y));
  if (frame.size() < 8) return 0.0;
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double centre = median(frame);
  for (double& v : frame) v = std::abs(v - centre);
  return 1.4826 * median(frame);
}

}  // namespace

MorphologyMeasures measureMorphology(const SourceStamp& stamp) {
  const ImageD& img = stamp.fluxPerPixel;
  const double total = totalFlux(stamp);
  if (!(total > 0.0) || img.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  Centroid c;
  for (std::int64_t y = 0; y < img.height(); ++y)
    for (std::int64_t x = 0; x < img.width(); ++x) {
      c.x += img(x, y) * double(x);
      c.y += img(x, y) * double(y);
    }
  c.x /= total;
  c.y /= total;
  const std::vector<double> r = radiiHolding(img, c, total, {0.2, 0.8});
  MorphologyMeasures m;
  m.concentration = r[0] > 0.0 ? 5.0 * std::log10(r[1] / r[0]) : 0.0;
  // The centroid of a lopsided galaxy is not its centre of symmetry: take the least A on a
  // half-pixel grid around it.
  const double noiseSigma = frameNoiseSigma(img);
  m.asymmetry = std::numeric_limits<double>::infinity();
  for (int dy = -4; dy <= 4; ++dy)
    for (int dx = -4; dx <= 4; ++dx)
      m.asymmetry = std::min(m.asymmetry, asymmetryAbout(img, {c.x + 0.5 * dx, c.y + 0.5 * dy},
                                                         1.5 * r[1], noiseSigma));
  return m;
}

GalaxyType classifyMorphology(const MorphologyMeasures& m) {
  if (m.asymmetry >= kIrregularAsymmetryMin) return GalaxyType::Irregular;
  if (m.concentration >= kEllipticalConcentrationMin) return GalaxyType::Elliptical;
  return GalaxyType::Spiral;
}

bool parseGalaxyType(const std::string& text, GalaxyType* type) {
  std::string t;
  for (char ch : text)
    if (!std::isspace(static_cast<unsigned char>(ch)))
      t += char(std::tolower(static_cast<unsigned char>(ch)));
  for (GalaxyType g : {GalaxyType::Elliptical, GalaxyType::Spiral, GalaxyType::Irregular})
    if (t == galaxyTypeName(g)) {
      *type = g;
      return true;
    }
  return false;
}

}  // namespace octarc::simulation
