// Helpers of the simulation tests: flux sums, Gaussian sources, and the lens equation solved
// numerically (the reference the analytic and ray-traced images are checked against).
#pragma once

#include <cmath>
#include <optional>

#include "octarc/core/Image.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/SourceStamp.h"

namespace octarc::test {

// Sum of every pixel, in double.
template <typename T>
double pixelSum(const Image<T>& image) {
  double s = 0.0;
  for (T v : image.pixels()) s += v;
  return s;
}

// A circular Gaussian source of width sigmaArcsec sampled at scaleArcsec on a (2 halfWidth + 1)^2
// stamp: of total flux 1, or, when `peak` is given, of that central value (not normalised).
inline simulation::SourceStamp gaussianSource(double sigmaArcsec, double scaleArcsec, int halfWidth,
                                              std::optional<double> peak = {}) {
  simulation::SourceStamp s;
  s.pixelScaleArcsec = scaleArcsec;
  s.fluxPerPixel = ImageD(2 * halfWidth + 1, 2 * halfWidth + 1);
  double total = 0.0;
  for (int y = 0; y <= 2 * halfWidth; ++y)
    for (int x = 0; x <= 2 * halfWidth; ++x) {
      const double r2 =
          (std::pow(x - halfWidth, 2) + std::pow(y - halfWidth, 2)) * scaleArcsec * scaleArcsec;
      const double shape = std::exp(-0.5 * r2 / (sigmaArcsec * sigmaArcsec));
      total += (s.fluxPerPixel(x, y) = peak ? *peak * shape : shape);
    }
  if (!peak)
    for (double& v : s.fluxPerPixel.pixels()) v /= total;
  s.name = "gaussian";
  return s;
}

// Newton iteration on beta(theta) = target, from `theta`, with the Jacobian by central
// differences.
inline simulation::Vec2 solveLensEquation(const simulation::EllipticalPotentialLens& lens,
                                          simulation::Vec2 theta, const simulation::Vec2& target) {
  for (int it = 0; it < 100; ++it) {
    const simulation::Vec2 beta = lens.sourcePositionArcsec(theta);
    const double fx = beta[0] - target[0];
    const double fy = beta[1] - target[1];
    if (std::hypot(fx, fy) < 1e-14) break;
    const double h = 1e-7;
    const simulation::Vec2 bxp = lens.sourcePositionArcsec({theta[0] + h, theta[1]});
    const simulation::Vec2 bxm = lens.sourcePositionArcsec({theta[0] - h, theta[1]});
    const simulation::Vec2 byp = lens.sourcePositionArcsec({theta[0], theta[1] + h});
    const simulation::Vec2 bym = lens.sourcePositionArcsec({theta[0], theta[1] - h});
    const double a = (bxp[0] - bxm[0]) / (2 * h), b = (byp[0] - bym[0]) / (2 * h);
    const double c = (bxp[1] - bxm[1]) / (2 * h), d = (byp[1] - bym[1]) / (2 * h);
    const double det = a * d - b * c;
    theta[0] -= (d * fx - b * fy) / det;
    theta[1] -= (-c * fx + a * fy) / det;
  }
  return theta;
}

}  // namespace octarc::test
