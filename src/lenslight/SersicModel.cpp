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
  // (r / r_e)^(1/n) as exp(log(r^2 / r_e^2) / 2n): no square root, and one logarithm where pow
  // takes more (the profile is most of the fits' time).
  const double inverseRe2 = 1.0 / (re * re), halfInverseN = 0.5 * inverseN;
  auto profile = [&](double dx, double dy) {
    const double major = c * dx + s * dy;
    const double minor = (-s * dx + c * dy) / q;
    const double r2 = (major * major + minor * minor) * inverseRe2;
    if (!(r2 > 0.0)) return std::exp(bn);
    return std::exp(-bn * (std::exp(halfInverseN * std::log(r2)) - 1.0));
  };
  // 2 x 2 Gauss-Legendre points on each of k x k sub-pixels: k = 10 within a pixel of the
  // centre, 5 within 2.5, 2 within five, 1 within ten, and the pixel's centre alone beyond (a
  // profile of n = 4 changes by orders of magnitude across the central pixel, and is smooth on the
  // scale of a pixel far from it: there the midpoint is off by about f''/24, a few 1e-3 of the
  // pixel's value; the fits draw the model hundreds of times, so the outer pixels are kept cheap).
  const double g = 0.5 / std::sqrt(3.0);
  ImageD image(width, height, 0.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double dx0 = x - p.xPix, dy0 = y - p.yPix;
      const double distance2 = dx0 * dx0 + dy0 * dy0;
      if (distance2 >= 100.0) {
        image(x, y) = intensity * profile(dx0, dy0);
        continue;
      }
      const int k = distance2 < 1.0 ? 10 : distance2 < 6.25 ? 5 : distance2 < 25.0 ? 2 : 1;
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
