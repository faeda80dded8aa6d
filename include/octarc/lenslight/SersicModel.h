// A smooth model of a lens galaxy's light: an elliptical Sersic profile, integrated over each
// pixel and convolved with a circular Gaussian PSF (METHOD.md section 5: subtracting it lets an
// arc inside the lens's halo separate at some threshold).
//
// Pixel coordinates are 0-based within the stamp (core/Conventions.h); the position angle is
// the major axis, counter-clockwise from +x, as in the lens simulator (simulation/LensLight.h).
#pragma once

#include "octarc/core/Image.h"

namespace octarc::lenslight {

struct SersicParams {
  double xPix = 0.0, yPix = 0.0;    // centre, 0-based stamp pixels
  double totalFluxAdu = 1.0;        // flux of the whole (infinite) profile
  double halfLightRadiusPix = 1.0;  // along the major axis
  double sersicIndex = 4.0;         // 4 = de Vaucouleurs, 1 = exponential
  double axisRatio = 1.0;           // b/a, (0, 1]
  double positionAngleRad = 0.0;    // major axis from +x, counter-clockwise
};

// Surface brightness at the half-light radius (ADU per pixel^2) of a profile of that total
// flux: L = 2 pi n q I_e r_e^2 e^b_n b_n^(-2n) Gamma(2n).
double sersicIntensityAtRe(const SersicParams& params);

// The profile integrated over each pixel of a width x height stamp (Gauss-Legendre points on
// sub-pixels, finer near the centre, where an n = 4 profile has its cusp), then convolved with
// a Gaussian PSF of `psfSigmaPix` (none when 0). Flux beyond the stamp is not drawn.
// ConfigError for a non-positive radius or index or an axis ratio outside (0, 1].
ImageD renderSersic(const SersicParams& params, int width, int height, double psfSigmaPix);

}  // namespace octarc::lenslight
