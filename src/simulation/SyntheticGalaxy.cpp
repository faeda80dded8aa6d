#include "octarc/simulation/SyntheticGalaxy.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/simulation/LensLight.h"

namespace octarc::simulation {

namespace {

// Evaluates f (arcsec offsets from the stamp centre) with 2x2 sub-samples per pixel, scales the
// result to `flux` and adds it to the stamp. Pixels outside the stamp's inscribed circle stay
// zero: a round support keeps the ray tracer's bounding circle (and so its cost) small.
void addComponent(ImageD& stamp, double scale, double flux,
                  const std::function<double(double, double)>& f) {
  const double cx = 0.5 * (stamp.width() - 1);
  const double cy = 0.5 * (stamp.height() - 1);
  const double radius2 = cx * cx;
  ImageD layer(stamp.width(), stamp.height());
  double sum = 0.0;
  for (std::int64_t y = 0; y < stamp.height(); ++y)
    for (std::int64_t x = 0; x < stamp.width(); ++x) {
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > radius2) continue;
      double v = 0.0;
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i)
          v += f((x - cx - 0.25 + 0.5 * i) * scale, (y - cy - 0.25 + 0.5 * j) * scale);
      layer(x, y) = v;
      sum += v;
    }
  if (!(sum > 0.0)) return;
  for (std::int64_t k = 0; k < stamp.size(); ++k) stamp[k] += flux * layer[k] / sum;
}

// Elliptical radius in the frame of position angle pa and axis ratio q.
struct EllipseFrame {
  double cx = 0.0, cy = 0.0, c = 1.0, s = 0.0, q = 1.0;
  EllipseFrame(double centreX, double centreY, double paRad, double axisRatio)
      : cx(centreX), cy(centreY), c(std::cos(paRad)), s(std::sin(paRad)), q(axisRatio) {}
  double major(double x, double y) const { return c * (x - cx) + s * (y - cy); }
  double minor(double x, double y) const { return (-s * (x - cx) + c * (y - cy)) / q; }
  double radius(double x, double y) const { return std::hypot(major(x, y), minor(x, y)); }
};

std::function<double(double, double)> sersic(const EllipseFrame& e, double n, double re) {
  const double bn = sersicBn(n);
  return [e, n, re, bn](double x, double y) {
    return std::exp(-bn * std::pow(e.radius(x, y) / re, 1.0 / n));
  };
}

std::function<double(double, double)> gaussian(double cx, double cy, double sigma) {
  return [cx, cy, sigma](double x, double y) {
    const double r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
    return std::exp(-0.5 * r2 / (sigma * sigma));
  };
}

}  // namespace

SourceStamp makeSyntheticGalaxy(GalaxyType type, std::mt19937_64& rng,
                                const SyntheticGalaxyOptions& options) {
  const double scale = options.pixelScaleArcsec;
  const double rh = options.halfLightRadiusArcsec;
  if (!(scale > 0.0) || !(rh > 0.0) || !(options.stampHalfLightRadii > 0.0))
    throw ConfigError(
        "synthetic galaxy: pixel scale, half-light radius and stamp size must be "
        "positive");
  const auto half = static_cast<std::int64_t>(std::ceil(options.stampHalfLightRadii * rh / scale));
  SourceStamp out;
  out.fluxPerPixel = ImageD(2 * half + 1, 2 * half + 1);
  out.pixelScaleArcsec = scale;
  out.type = type;
  ImageD& img = out.fluxPerPixel;

  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  const double pa = uniform(0.0, std::numbers::pi);

  switch (type) {
    case GalaxyType::Elliptical: {
      const double q = uniform(0.6, 1.0);
      const double envelopeFraction = uniform(0.05, 0.15);
      addComponent(img, scale, 1.0 - envelopeFraction, sersic({0, 0, pa, q}, 4.0, rh));
      addComponent(img, scale, envelopeFraction, sersic({0, 0, pa, q}, 1.0, 2.0 * rh));
      break;
    }
    case GalaxyType::Spiral: {
      const double q = uniform(0.3, 1.0);  // disc axis ratio, cos(inclination) for a thin disc
      const double bulgeFraction = uniform(0.05, 0.35);
      const double clumpFraction = uniform(0.05, 0.2);
      const double discFraction = 1.0 - bulgeFraction - clumpFraction;
      addComponent(img, scale, bulgeFraction, sersic({0, 0, pa, std::max(q, 0.7)}, 4.0, 0.35 * rh));
      // Exponential disc with two logarithmic spiral arms of pitch angle 10-30 degrees.
      const EllipseFrame disc(0, 0, pa, q);
      const double tanPitch = std::tan(uniform(10.0, 30.0) * std::numbers::pi / 180.0);
      const double armPhase = uniform(0.0, 2.0 * std::numbers::pi);
      const double armContrast = uniform(0.4, 0.8);
      const double bDisc = sersicBn(1.0);
      auto armPhiAt = [=](double r) {
        return std::log(std::max(r, 1e-6) / rh) / tanPitch + armPhase;
      };
      addComponent(img, scale, discFraction, [=](double x, double y) {
        const double u = disc.major(x, y);
        const double v = disc.minor(x, y);
        const double r = std::hypot(u, v);
        const double phi = std::atan2(v, u);
        const double arms = 1.0 + armContrast * std::cos(2.0 * (phi - armPhiAt(r)));
        return std::exp(-bDisc * r / rh) * arms;
      });
      // Star-forming clumps on the arms.
      const int nClumps = std::uniform_int_distribution<int>(3, 8)(rng);
      for (int k = 0; k < nClumps; ++k) {
        const double r = uniform(0.4, 1.8) * rh;
        const double phi = armPhiAt(r) + (unit(rng) < 0.5 ? 0.0 : std::numbers::pi);
        const double u = r * std::cos(phi);
        const double v = r * std::sin(phi) * q;  // project the disc-plane position
        const double x = disc.c * u - disc.s * v;
        const double y = disc.s * u + disc.c * v;
        addComponent(img, scale, clumpFraction / nClumps,
                     gaussian(x, y, uniform(0.04, 0.1) * rh + 0.5 * scale));
      }
      break;
    }
    case GalaxyType::Irregular: {
      const double q = uniform(0.4, 1.0);
      const double clumpFraction = uniform(0.25, 0.5);
      const double lopsidedFraction = uniform(0.15, 0.3);
      const double mainFraction = 1.0 - clumpFraction - lopsidedFraction;
      addComponent(img, scale, mainFraction, sersic({0, 0, pa, q}, 1.0, rh));
      const double offsetAngle = uniform(0.0, 2.0 * std::numbers::pi);
      const double offset = uniform(0.3, 0.7) * rh;
      addComponent(img, scale, lopsidedFraction,
                   sersic({offset * std::cos(offsetAngle), offset * std::sin(offsetAngle),
                           uniform(0.0, std::numbers::pi), uniform(0.4, 1.0)},
                          1.0, 0.6 * rh));
      const int nClumps = std::uniform_int_distribution<int>(4, 10)(rng);
      std::vector<double> weights(nClumps);
      double wsum = 0.0;
      for (double& w : weights) wsum += (w = uniform(0.5, 1.5));
      for (int k = 0; k < nClumps; ++k) {
        const double r = rh * 1.3 * std::sqrt(unit(rng));
        const double phi = uniform(0.0, 2.0 * std::numbers::pi);
        addComponent(
            img, scale, clumpFraction * weights[k] / wsum,
            gaussian(r * std::cos(phi), r * std::sin(phi), uniform(0.06, 0.18) * rh + 0.5 * scale));
      }
      break;
    }
  }
  out.name = std::string("synthetic ") + galaxyTypeName(type);
  return out;
}

}  // namespace octarc::simulation
