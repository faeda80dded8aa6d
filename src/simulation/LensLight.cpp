#include "octarc/simulation/LensLight.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "octarc/core/Error.h"

namespace octarc::simulation {

double regularizedGammaP(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 0.0;
  const double logPrefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    // Series: P = x^a e^-x / Gamma(a+1) * sum_k x^k / ((a+1)...(a+k)).
    double term = 1.0 / a;
    double sum = term;
    for (int k = 1; k < 10000; ++k) {
      term *= x / (a + k);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-17) break;
    }
    return sum * std::exp(logPrefactor);
  }
  // Continued fraction for Q = 1 - P (modified Lentz).
  const double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(logPrefactor) * h;
}

double sersicBn(double n) {
  if (!(n > 0.0)) throw ConfigError("Sersic index must be positive, got " + std::to_string(n));
  // P(2n, b) is increasing in b; bisect on [0, 4n + 2] (b_n < 2n for all n > 0.36, and the bracket
  // is generous for small n).
  double lo = 0.0;
  double hi = 4.0 * n + 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-14 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (regularizedGammaP(2.0 * n, mid) < 0.5 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double sersicEnclosedFraction(double n, double radiusOverRe) {
  return regularizedGammaP(2.0 * n, sersicBn(n) * std::pow(radiusOverRe, 1.0 / n));
}

double fluxFromMagnitude(double mag, double magZeroPoint) {
  return std::pow(10.0, -0.4 * (mag - magZeroPoint));
}

void addSersicLight(ImageD& image, const SurveyGrid& grid, const SersicLightParams& params) {
  const double n = params.sersicIndex;
  const double re = params.halfLightRadiusArcsec;
  const double q = params.axisRatio;
  if (!(n > 0.0) || !(re > 0.0) || !(q > 0.0 && q <= 1.0))
    throw ConfigError(
        "lens light: need Sersic index > 0, half-light radius > 0 and axis ratio "
        "in (0, 1], got " +
        std::to_string(n) + ", " + std::to_string(re) + "\", " + std::to_string(q));
  if (image.width() != grid.width || image.height() != grid.height)
    throw ConfigError("lens light: image size differs from the survey grid");
  const double bn = sersicBn(n);
  // Total flux of the infinite profile: 2 pi n q I_e r_e^2 e^b b^-2n Gamma(2n).
  const double norm = 2.0 * std::numbers::pi * n * q * re * re *
                      std::exp(bn + std::lgamma(2.0 * n) - 2.0 * n * std::log(bn));
  const double intensityAtRe = params.totalFlux / norm;  // flux per arcsec^2 at r_e
  // x^(1/n), with the de Vaucouleurs case as two square roots (much faster than pow).
  auto rootN = [n](double x) { return n == 4.0 ? std::sqrt(std::sqrt(x)) : std::pow(x, 1.0 / n); };
  const double c = std::cos(params.positionAngleRad);
  const double sn = std::sin(params.positionAngleRad);
  auto profile = [&](double ox, double oy) {
    const double major = c * ox + sn * oy;
    const double minor = (-sn * ox + c * oy) / q;
    return std::exp(-bn * (rootN(std::sqrt(major * major + minor * minor) / re) - 1.0));
  };
  // Integral of the profile over the square of half-size h centred at (ox, oy) (arcsec from the
  // profile centre), by adaptive subdivision: a square is split in four while it is close to the
  // centre compared with its size (the cusp) or larger than a quarter of the profile's local
  // scale length |I / I'| = q (n r_e / b_n) (r / r_e)^(1 - 1/n) (r = distance, a lower bound of
  // the elliptical radius; q for the steeper minor axis). Leaves use 3x3 Gauss-Legendre points.
  constexpr int kMaxDepth = 14;
  // x^(1 - 1/n); for de Vaucouleurs x^(3/4) = sqrt(x) sqrt(sqrt(x)), without pow.
  auto rootPower = [n](double x) {
    if (n == 4.0) {
      const double r2 = std::sqrt(x);
      return r2 * std::sqrt(r2);
    }
    return std::pow(x, 1.0 - 1.0 / n);
  };
  const double scaleLengthFactor = q * n * re / bn;
  const double gl = std::sqrt(0.6);
  const double glNodes[3] = {-gl, 0.0, gl};
  const double glWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const auto integrate = [&](auto&& self, double ox, double oy, double h, int depth) -> double {
    const double dist2 = ox * ox + oy * oy;
    if (depth < kMaxDepth) {
      const double dist = std::sqrt(dist2);
      const double scaleLength = scaleLengthFactor * rootPower(dist / re);
      if (dist2 < 16.0 * h * h || h > 0.25 * scaleLength) {
        const double k = 0.5 * h;
        return self(self, ox - k, oy - k, k, depth + 1) + self(self, ox + k, oy - k, k, depth + 1) +
               self(self, ox - k, oy + k, k, depth + 1) + self(self, ox + k, oy + k, k, depth + 1);
      }
    }
    // A square small against the local scale length L needs fewer points: the midpoint rule
    // (relative error of order (h / L)^2 / 6, < 4e-4) or 2 x 2 Gauss-Legendre points (order
    // (h / L)^4 / 135, < 4e-6) instead of nine evaluations.
    if (dist2 >= 16.0 * h * h) {
      const double scaleLength = scaleLengthFactor * rootPower(std::sqrt(dist2) / re);
      if (h < 0.05 * scaleLength) return 4.0 * h * h * profile(ox, oy);
      if (h < 0.15 * scaleLength) {
        const double g = h / std::sqrt(3.0);
        return h * h *
               (profile(ox - g, oy - g) + profile(ox + g, oy - g) + profile(ox - g, oy + g) +
                profile(ox + g, oy + g));
      }
    }
    double sum = 0.0;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        sum += glWeights[i] * glWeights[j] * profile(ox + glNodes[i] * h, oy + glNodes[j] * h);
    return sum * h * h;  // weights sum to 2 per axis over [-h, h]: (2h)^2 / 4 * sum
  };
  const double s = grid.pixelScaleArcsec;
  for (std::int64_t y = 0; y < image.height(); ++y)
    for (std::int64_t x = 0; x < image.width(); ++x)
      image(x, y) += intensityAtRe * integrate(integrate, (x - grid.lensXPix) * s,
                                               (y - grid.lensYPix) * s, 0.5 * s, 0);
}

}  // namespace octarc::simulation
