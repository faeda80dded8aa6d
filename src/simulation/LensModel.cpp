#include "octarc/simulation/LensModel.h"

#include <cmath>
#include <numbers>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/simulation/Cosmology.h"

namespace octarc::simulation {

double sisEinsteinRadiusArcsec(double sigmaKmPerS, double zLens, double zSource,
                               const FlatLambdaCdm& cosmology) {
  if (!(sigmaKmPerS > 0.0))
    throw ConfigError("lens: velocity dispersion must be positive, got " +
                      std::to_string(sigmaKmPerS));
  if (!(zLens > 0.0) || !(zSource > zLens))
    throw ConfigError("lens: need 0 < z_lens < z_source, got z_lens " + std::to_string(zLens) +
                      ", z_source " + std::to_string(zSource));
  const double dLs = cosmology.angularDiameterDistanceMpc(zLens, zSource);
  const double dS = cosmology.angularDiameterDistanceMpc(zSource);
  const double beta = sigmaKmPerS / kSpeedOfLightKmPerS;
  return 4.0 * std::numbers::pi * beta * beta * dLs / dS * kArcsecPerRad;
}

double potentialEllipticityFromLight(double lightEllipticity) {
  if (!(lightEllipticity >= 0.0 && lightEllipticity < 1.0))
    throw ConfigError("lens: light ellipticity must be in [0, 1), got " +
                      std::to_string(lightEllipticity));
  return 0.2 * lightEllipticity / (0.6 + lightEllipticity);
}

EllipticalPotentialLens::EllipticalPotentialLens(const EllipticalPotentialParams& params)
    : params_(params),
      cosPa_(std::cos(params.positionAngleRad)),
      sinPa_(std::sin(params.positionAngleRad)),
      core2_(params.coreArcsec * params.coreArcsec),
      oneMinusEps_(1.0 - params.ellipticity),
      onePlusEps_(1.0 + params.ellipticity),
      bOneMinusEps_(params.einsteinRadiusArcsec * (1.0 - params.ellipticity)),
      bOnePlusEps_(params.einsteinRadiusArcsec * (1.0 + params.ellipticity)) {
  if (!(params.einsteinRadiusArcsec > 0.0))
    throw ConfigError("lens: Einstein radius must be positive, got " +
                      std::to_string(params.einsteinRadiusArcsec));
  if (!(params.ellipticity >= 0.0 && params.ellipticity < 1.0))
    throw ConfigError("lens: potential ellipticity must be in [0, 1), got " +
                      std::to_string(params.ellipticity));
  if (!(params.coreArcsec >= 0.0))
    throw ConfigError("lens: core radius must be >= 0, got " + std::to_string(params.coreArcsec));
}

double EllipticalPotentialLens::potentialArcsec2(const Vec2& theta) const {
  const double x = cosPa_ * theta[0] + sinPa_ * theta[1];
  const double y = -sinPa_ * theta[0] + cosPa_ * theta[1];
  const double eps = params_.ellipticity;
  const double tc = params_.coreArcsec;
  return params_.einsteinRadiusArcsec *
         std::sqrt(tc * tc + (1.0 - eps) * x * x + (1.0 + eps) * y * y);
}

double EllipticalPotentialLens::magnification(const Vec2& theta) const {
  const double x = cosPa_ * theta[0] + sinPa_ * theta[1];
  const double y = -sinPa_ * theta[0] + cosPa_ * theta[1];
  const double a = 1.0 - params_.ellipticity;
  const double c = 1.0 + params_.ellipticity;
  const double tc = params_.coreArcsec;
  const double d = std::sqrt(tc * tc + a * x * x + c * y * y);
  const double b = params_.einsteinRadiusArcsec;
  // Hessian of psi in the lens frame; the determinant is rotation invariant.
  const double d3 = d * d * d;
  const double psiXx = b * a / d - b * a * a * x * x / d3;
  const double psiYy = b * c / d - b * c * c * y * y / d3;
  const double psiXy = -b * a * c * x * y / d3;
  const double det = (1.0 - psiXx) * (1.0 - psiYy) - psiXy * psiXy;
  return 1.0 / det;
}

double EllipticalPotentialLens::maxDeflectionArcsec() const {
  return params_.einsteinRadiusArcsec * std::sqrt(1.0 + params_.ellipticity);
}

double EllipticalPotentialLens::maxDeflectionGradient(double minDArcsec) const {
  // Hessian = (b/D) (M - M t t^T M / D^2) with M = diag(1-eps, 1+eps): positive semi-definite and
  // bounded above by (b/D) M, whose largest eigenvalue is b (1+eps) / D.
  return (1.0 + params_.ellipticity) * params_.einsteinRadiusArcsec / minDArcsec;
}

}  // namespace octarc::simulation
