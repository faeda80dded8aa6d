// The lens mass model: the elliptical potential with a core of Blandford & Kochanek (1987), as
// written in METHOD.md section 3, and the SIS Einstein radius.
//
// Coordinates: angles in arcsec on the sky, relative to the lens centre, x and y along the image
// axes. The lens frame is rotated by positionAngleRad (counter-clockwise from +x, see
// core/Conventions.h) so that its x axis is the major axis of the lens light.
#pragma once

#include <array>
#include <cmath>

namespace octarc::simulation {

class FlatLambdaCdm;

// SIS Einstein radius b = 4 pi (sigma_v / c)^2 D_ls / D_s, in arcsec. Throws ConfigError unless
// 0 < zLens < zSource and sigma > 0.
double sisEinsteinRadiusArcsec(double sigmaKmPerS, double zLens, double zSource,
                               const FlatLambdaCdm& cosmology);

// Potential ellipticity from the light ellipticity e_l = 1 - b/a: eps = 0.2 e_l / (0.6 + e_l),
// so 0 <= eps < 0.2 for 0 <= e_l < 1 (the surface density stays positive).
double potentialEllipticityFromLight(double lightEllipticity);

struct EllipticalPotentialParams {
  double einsteinRadiusArcsec = 1.0;  // b
  double ellipticity = 0.0;           // eps, 0 <= eps < 1
  double coreArcsec = 0.0;            // theta_c
  double positionAngleRad = 0.0;      // major axis, counter-clockwise from +x
};

using Vec2 = std::array<double, 2>;

class EllipticalPotentialLens {
 public:
  // Throws ConfigError for b <= 0, eps outside [0, 1) or a negative core.
  explicit EllipticalPotentialLens(const EllipticalPotentialParams& params);

  const EllipticalPotentialParams& params() const { return params_; }
  // psi(theta) = b sqrt(theta_c^2 + (1 - eps) x^2 + (1 + eps) y^2), (x, y) in the lens frame;
  // arcsec^2.
  double potentialArcsec2(const Vec2& thetaArcsec) const;
  // alpha = grad psi, arcsec, in sky axes. Zero at the centre when theta_c = 0 (the limit does
  // not exist there; the centre is a single point of zero measure). Inline: the ray tracer calls
  // it for every ray.
  Vec2 deflectionArcsec(const Vec2& thetaArcsec) const {
    const double x = cosPa_ * thetaArcsec[0] + sinPa_ * thetaArcsec[1];
    const double y = -sinPa_ * thetaArcsec[0] + cosPa_ * thetaArcsec[1];
    const double d2 = core2_ + oneMinusEps_ * x * x + onePlusEps_ * y * y;
    if (d2 == 0.0) return {0.0, 0.0};
    const double invD = 1.0 / std::sqrt(d2);
    const double ax = bOneMinusEps_ * x * invD;
    const double ay = bOnePlusEps_ * y * invD;
    // Back from the lens frame to sky axes.
    return {cosPa_ * ax - sinPa_ * ay, sinPa_ * ax + cosPa_ * ay};
  }
  // beta = theta - alpha(theta).
  Vec2 sourcePositionArcsec(const Vec2& thetaArcsec) const {
    const Vec2 alpha = deflectionArcsec(thetaArcsec);
    return {thetaArcsec[0] - alpha[0], thetaArcsec[1] - alpha[1]};
  }
  // Signed magnification 1 / det(d beta / d theta) from the analytic Hessian of psi.
  double magnification(const Vec2& thetaArcsec) const;
  // Upper bound of |alpha| over the whole plane: b sqrt(1 + eps).
  double maxDeflectionArcsec() const;
  // Upper bound of the spectral norm of d alpha / d theta over points whose lens-frame
  // D = sqrt(theta_c^2 + (1-eps) x^2 + (1+eps) y^2) is at least minD (arcsec): (1 + eps) b / minD.
  double maxDeflectionGradient(double minDArcsec) const;

 private:
  EllipticalPotentialParams params_;
  double cosPa_ = 1.0;
  double sinPa_ = 0.0;
  double core2_ = 0.0;         // theta_c^2
  double oneMinusEps_ = 1.0;   // 1 - eps
  double onePlusEps_ = 1.0;    // 1 + eps
  double bOneMinusEps_ = 1.0;  // b (1 - eps)
  double bOnePlusEps_ = 1.0;   // b (1 + eps)
};

}  // namespace octarc::simulation
