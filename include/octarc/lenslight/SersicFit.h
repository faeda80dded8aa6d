// Fitting the Sersic model (SersicModel.h) to a background-subtracted cut-out around a bright
// galaxy, by least squares with Ceres Solver, and the residual in which an arc inside the
// galaxy's halo can be detected.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/lenslight/SersicModel.h"

namespace octarc::lenslight {

struct SersicFitSettings {
  double psfSigmaPix = 0.0;  // Gaussian PSF of the image (sigma, pixels); 0: none
  // Per fit; a lens galaxy converges in a few tens, what runs on is a star or a blend (flagged).
  int maxIterations = 60;
  // The half-light radius is fitted within [minHalfLightRadiusPix, the stamp's half side] (before
  // the swap of axes that keeps the axis ratio at most 1, SersicFit.cpp).
  double minHalfLightRadiusPix = 0.5;
  // Bounds of the index and the axis ratio (a de Vaucouleurs lens sits well inside).
  double minIndex = 0.3, maxIndex = 8.0;
  double minAxisRatio = 0.05;  // the axis ratio is fitted smoothly through 1 (SersicFit.cpp)
};

struct SersicFitResult {
  SersicParams params;
  // One-sigma errors from the covariance of the fit (the pixel variances as given); NaN when
  // it cannot be computed (a singular problem, e.g. the angle of a round galaxy, or a fit that
  // stopped on a failure).
  SersicParams errors;
  double chi2 = 0.0;
  std::int64_t degreesOfFreedom = 0;
  bool converged = false;
  bool radiusAtLimit = false;  // the fitted radius ended on one of its bounds (a star, a blend)
  int iterations = 0;
  std::string message;  // the solver's report when it did not converge
};

// SersicFitResult::message when the stamp has no more usable pixels than parameters.
inline constexpr const char* kTooFewPixelsMessage = "too few pixels to fit";

// A starting point from the stamp's own moments (positive pixels only): centroid, axis ratio and
// angle of the second moments, flux = sum, radius about the moments' size, index 2.5.
SersicParams momentsStart(const ImageD& stamp);

// Least-squares fit of the model to `stamp` with per-pixel variances `varianceAdu2` (same size;
// a pixel with a non-finite or non-positive variance is left out) and pixels where
// `ignored` is non-zero (empty: none) left out; from `start`.
SersicFitResult fitSersic(const ImageD& stamp, const ImageD& varianceAdu2,
                          const std::vector<std::uint8_t>& ignored, const SersicParams& start,
                          const SersicFitSettings& settings);

struct LensLightSettings {
  SersicFitSettings fit;
  // Pixels whose residual, smoothed over 3 x 3 pixels, is above clipSigma times its noise are
  // left out of the next fit (an arc, a neighbour), `clipRounds` times.
  double clipSigma = 3.0;
  int clipRounds = 3;
};

struct LensLightModel {
  SersicFitResult fit;
  ImageD model;                       // the fitted model on the stamp
  ImageD residual;                    // stamp - model
  std::vector<std::uint8_t> clipped;  // pixels the last fit left out
};

// The lens galaxy of `stamp` fitted with its positive outliers clipped round by round, so that an
// arc in its halo does not pull the model, and the residual.
LensLightModel fitLensLight(const ImageD& stamp, const ImageD& varianceAdu2,
                            const LensLightSettings& settings);
// The same from a given start (momentsStart(stamp) above).
LensLightModel fitLensLightFrom(const ImageD& stamp, const ImageD& varianceAdu2,
                                const SersicParams& start, const LensLightSettings& settings);

}  // namespace octarc::lenslight
