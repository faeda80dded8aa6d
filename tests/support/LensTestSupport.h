// Helpers of the simulation tests: flux sums, Gaussian sources, and the lens equation solved
// numerically (the reference the analytic and ray-traced images are checked against).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

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

// A uniform disc of radius radiusArcsec and total flux 1 on a (2 halfWidth + 1)^2 stamp of
// scaleArcsec pixels, each edge pixel holding the covered fraction (8 x 8 sub-samples).
inline simulation::SourceStamp uniformDiscSource(double radiusArcsec, double scaleArcsec,
                                                 int halfWidth) {
  simulation::SourceStamp s;
  s.pixelScaleArcsec = scaleArcsec;
  s.fluxPerPixel = ImageD(2 * halfWidth + 1, 2 * halfWidth + 1);
  constexpr int kSub = 8;
  double total = 0.0;
  for (int y = 0; y <= 2 * halfWidth; ++y)
    for (int x = 0; x <= 2 * halfWidth; ++x) {
      int inside = 0;
      for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
          const double dx = (x - halfWidth + (i + 0.5) / kSub - 0.5) * scaleArcsec;
          const double dy = (y - halfWidth + (j + 0.5) / kSub - 0.5) * scaleArcsec;
          if (dx * dx + dy * dy <= radiusArcsec * radiusArcsec) ++inside;
        }
      total += (s.fluxPerPixel(x, y) = double(inside) / (kSub * kSub));
    }
  for (double& v : s.fluxPerPixel.pixels()) v /= total;
  s.name = "uniform disc";
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

// The number of images of a point source at beta for a coreless lens, found independently of
// any caustic: along each direction u the deflection alpha(u) does not depend on the radius, so
// theta = r u is an image when beta + alpha(u) = r u with r > 0, i.e. at the zeros of
// u x (beta + alpha(u)) where u . (beta + alpha(u)) > 0. Sign changes on `steps` directions.
inline int countImagesCoreless(const simulation::EllipticalPotentialLens& lens,
                               const simulation::Vec2& beta, int steps = 20000) {
  auto cross = [&](double phi, double* along) {
    const simulation::Vec2 u{std::cos(phi), std::sin(phi)};
    const simulation::Vec2 a = lens.deflectionArcsec(u);
    *along = u[0] * (beta[0] + a[0]) + u[1] * (beta[1] + a[1]);
    return u[0] * (beta[1] + a[1]) - u[1] * (beta[0] + a[0]);
  };
  int images = 0;
  double along = 0.0;
  double previous = cross(0.0, &along);
  for (int k = 1; k <= steps; ++k) {
    double alongHere = 0.0;
    const double here = cross(2.0 * 3.14159265358979323846 * k / steps, &alongHere);
    if ((previous < 0.0) != (here < 0.0) && along + alongHere > 0.0) ++images;
    previous = here;
    along = alongHere;
  }
  return images;
}

// Kolmogorov-Smirnov distance between a sample and a CDF.
template <typename Cdf>
double ksDistance(std::vector<double> sample, Cdf cdf) {
  std::sort(sample.begin(), sample.end());
  double d = 0.0;
  const double n = double(sample.size());
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const double f = cdf(sample[i]);
    d = std::max({d, std::abs(f - double(i) / n), std::abs(double(i + 1) / n - f)});
  }
  return d;
}

// Integral of f on [a, b] by Simpson's rule on n (even) intervals.
template <typename F>
double simpson(F f, double a, double b, int n = 2000) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return s * h / 3.0;
}

}  // namespace octarc::test
