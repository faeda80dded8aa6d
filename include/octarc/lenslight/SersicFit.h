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
  // A positive residual of r sigma costs c^2 log(1 + (r/c)^2) with c = robustScaleSigma, a
  // negative one r^2: light the model lacks (an arc, a ring, a neighbour) pulls the fit far less
  // than in plain least squares, light it has too much of as much. 0: plain least squares.
  double robustScaleSigma = 0.0;
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
  // stopped on a failure, or a robust fit: robustScaleSigma > 0).
  SersicParams errors;
  double chi2 = 0.0;  // twice the final cost: chi^2, or its robust form with robustScaleSigma
  std::int64_t degreesOfFreedom = 0;
  bool converged = false;
  bool radiusAtLimit = false;  // the fitted radius ended on one of its bounds (a star, a blend)
  // The index or the axis ratio ended on one of its bounds: a profile the model does not hold
  // (a ring pulling the index up, a star), or a fit eaten by what it should have left out.
  bool shapeAtBound = false;
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
  // The first fit uses the one-sided robust cost of this scale (SersicFitSettings), so that an
  // arc or a ring does not pull it; then pixels whose residual, smoothed over 3 x 3 pixels, is
  // above clipSigma times its noise, and their neighbours, are left out of a plain least-squares
  // fit from there (the errors are those of that fit), at most `clipRounds` times.
  double robustScaleSigma = 2.0;
  // The robust fit is only the masked fit's start: a few steps of it take the arc out of the
  // way (it converges in 10 to 60 on bright galaxies, the masked fit from there in 3 to 15).
  int robustMaxIterations = 12;
  double clipSigma = 3.0;
  int clipRounds = 1;
};

struct LensLightModel {
  SersicFitResult fit;
  ImageD model;                       // the fitted model on the stamp
  ImageD residual;                    // stamp - model
  std::vector<std::uint8_t> clipped;  // pixels the last fit left out
};

// The lens galaxy of `stamp` fitted robustly, then with its positive outliers masked, so that an
// arc in its halo does not pull the model, and the residual.
LensLightModel fitLensLight(const ImageD& stamp, const ImageD& varianceAdu2,
                            const LensLightSettings& settings);
// The same from a given start (momentsStart(stamp) above).
LensLightModel fitLensLightFrom(const ImageD& stamp, const ImageD& varianceAdu2,
                                const SersicParams& start, const LensLightSettings& settings);

}  // namespace octarc::lenslight
