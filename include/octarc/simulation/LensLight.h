// Light of the lens galaxy: a de Vaucouleurs (Sersic n = 4) profile (METHOD.md section 3).
#pragma once

#include "octarc/core/Image.h"
#include "octarc/simulation/RayTracer.h"

namespace octarc::simulation {

// Regularised lower incomplete gamma function P(a, x) (series for x < a + 1, continued fraction
// otherwise), a > 0, x >= 0.
double regularizedGammaP(double a, double x);

// The Sersic b_n that makes r_e the half-light radius: P(2n, b_n) = 1/2 (b_4 = 7.66925...).
double sersicBn(double n);

// Fraction of a Sersic profile's total flux inside radius r (elliptical radius for q < 1):
// P(2n, b_n (r/r_e)^(1/n)).
double sersicEnclosedFraction(double n, double radiusOverRe);

// Flux (ADU) of magnitude mag at zero point magZeroPoint: 10^(-0.4 (mag - zp)).
double fluxFromMagnitude(double mag, double magZeroPoint);

struct SersicLightParams {
  double sersicIndex = 4.0;            // 4 = de Vaucouleurs
  double halfLightRadiusArcsec = 1.0;  // along the major axis
  double axisRatio = 1.0;              // b/a, (0, 1]
  double positionAngleRad = 0.0;       // major axis, counter-clockwise from +x
  double totalFlux = 1.0;              // flux of the whole (infinite) profile
};

// Adds the profile centred on the grid's lens position (grid.lensXPix, lensYPix) to `image`
// (width x height of the grid, flux per pixel). Each pixel is the profile integrated over the
// pixel (adaptive subdivision towards the cusp, so even r_e ~ 1 pixel is drawn to ~1e-4 of the
// flux). Flux beyond the stamp is not drawn.
// Throws ConfigError for non-positive radius, axis ratio outside (0, 1] or index <= 0.
void addSersicLight(ImageD& image, const SurveyGrid& grid, const SersicLightParams& params);

}  // namespace octarc::simulation
