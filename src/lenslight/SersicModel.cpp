#include "octarc/lenslight/SersicModel.h"

#include <cmath>
#include <numbers>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Psf.h"

namespace octarc::lenslight {

namespace {

void checkParams(const SersicParams& p) {
  if (!(p.sersicIndex > 0.0) || !(p.halfLightRadiusPix > 0.0) ||
      !(p.axisRatio > 0.0 && p.axisRatio <= 1.0)) {
    throw ConfigError(
        "Sersic model: need index > 0, half-light radius > 0 and axis ratio in "
        "(0, 1], got " +
        std::to_string(p.sersicIndex) + ", " + std::to_string(p.halfLightRadiusPix) + " px, " +
        std::to_string(p.axisRatio));
  }
}

// The 1-D Gaussian PSF kernel taken at pixel centres: the model pixels already hold the flux
// falling on each pixel, so the pixel box is not applied twice (simulation/Psf.h).
std::vector<double> psfKernel(double sigmaPix) {
  const double fwhmPix = sigmaPix * 2.0 * std::sqrt(2.0 * std::log(2.0));
  return simulation::gaussianPsfKernel1d(fwhmPix, 1.0, simulation::PsfSampling::PointSampled);
}

}  // namespace

double sersicIntensityAtRe(const SersicParams& p) {
  checkParams(p);
  const double n = p.sersicIndex;
  const double bn = simulation::sersicBn(n);
  const double norm = 2.0 * std::numbers::pi * n * p.axisRatio * p.halfLightRadiusPix *
                      p.halfLightRadiusPix *
                      std::exp(bn + std::lgamma(2.0 * n) - 2.0 * n * std::log(bn));
  return p.totalFluxAdu / norm;
}

ImageD renderSersic(const SersicParams& p, int width, int height, double psfSigmaPix) {
  const double intensity = sersicIntensityAtRe(p);
  const double n = p.sersicIndex, re = p.halfLightRadiusPix, q = p.axisRatio;
  const double bn = simulation::sersicBn(n);
  const double c = std::cos(p.positionAngleRad), s = std::sin(p.positionAngleRad);
  const double inverseN = 1.0 / n;
  auto profile = [&](double dx, double dy) {
    const double major = c * dx + s * dy;
    const double minor = (-s * dx + c * dy) / q;
    const double r = std::sqrt(major * major + minor * minor) / re;
    return std::exp(-bn * (std::pow(r, inverseN) - 1.0));
  };
  // 2 x 2 Gauss-Legendre points on each of k x k sub-pixels: k = 15 within two pixels of the
  // centre, 6 within five, 2 within ten and 1 beyond (a profile of n = 4 changes by orders of
  // magnitude across the central pixel, and is smooth on the scale of a pixel far from it; the
  // fits draw the model hundreds of times, so the outer pixels are kept cheap).
  const double g = 0.5 / std::sqrt(3.0);
  ImageD image(width, height, 0.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double dx0 = x - p.xPix, dy0 = y - p.yPix;
      const double distance = std::hypot(dx0, dy0);
      const int k = distance < 2.0 ? 15 : distance < 5.0 ? 6 : distance < 10.0 ? 2 : 1;
      const double step = 1.0 / k;
      double sum = 0.0;
      for (int j = 0; j < k; ++j) {
        const double sy = dy0 - 0.5 + (j + 0.5) * step;
        for (int i = 0; i < k; ++i) {
          const double sx = dx0 - 0.5 + (i + 0.5) * step;
          sum += profile(sx - g * step, sy - g * step) + profile(sx + g * step, sy - g * step) +
                 profile(sx - g * step, sy + g * step) + profile(sx + g * step, sy + g * step);
        }
      }
      image(x, y) = intensity * sum * 0.25 * step * step;
    }
  }
  if (psfSigmaPix > 0.0) image = simulation::convolveSeparable(image, psfKernel(psfSigmaPix));
  return image;
}

}  // namespace octarc::lenslight
