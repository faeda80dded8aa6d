// Ray tracing of a source stamp through a lens onto a survey-pixel grid (METHOD.md section 3).
//
// What is done, exactly:
//   1. The survey stamp (width x height survey pixels) is covered by a lens-plane grid of
//      square fine pixels of exactly fineScaleArcsec, starting at the stamp's lower-left corner
//      (the survey/fine ratio is in general not an integer, e.g. 0.257/0.03 ~ 8.57; the last
//      fine row and column may stick out of the stamp, and that part is cut in step 4).
//   2. Each fine pixel is split into subSamples x subSamples sub-pixels (or, with adaptive
//      sampling, fewer where the lens map compresses the pixel's image; see RayTraceOptions); the
//      ray through each
//      sub-pixel centre is mapped to the source plane by the lens equation beta = theta - alpha,
//      and the source surface brightness there is bilinearly interpolated from the stamp
//      (surface brightness = pixel flux / stamp pixel area; zero outside the stamp). The fine
//      pixel's flux is the mean surface brightness times its area.
//   3. Fine pixels whose rays cannot reach the source are skipped without tracing, tested first
//      per block of blockFinePixels^2 fine pixels, then per fine pixel: the deflection is
//      evaluated once at the square's centre, its change across the square is bounded by
//      (1 + eps) b / D_min times the half-diagonal (D_min: the smallest lens-frame D in the
//      square), and if no ray can then land within the circle holding the stamp's non-zero
//      pixels, the square stays zero. The skipping is exact: the result is identical to tracing
//      every ray.
//   4. The fine grid is rebinned to the survey pixels conserving flux: each traced fine pixel's
//      flux goes straight to the survey pixels it overlaps, with rebinFluxConserving's overlap
//      fractions (no fine-grid image is kept).
// Surface brightness is conserved by lensing, so the traced flux is the source flux times the
// magnification.
#pragma once

#include "octarc/core/Image.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

struct RayTraceOptions {
  double fineScaleArcsec = 0.03;  // lens-plane grid step (the source stamp scale in the paper)
  int subSamples = 4;             // rays per fine pixel along each axis (the most, when adaptive)
  // Adaptive sub-sampling: along each sky axis a fine pixel gets the fewest rays, up to
  // subSamples, whose source-plane spacing is at most this many source-stamp pixels (from the
  // lens map's Jacobian at the pixel's centre): where the lens compresses the pixel's image
  // (magnification), one ray samples it as well as sixteen. 0 traces subSamples^2 everywhere.
  double maxSourceStepPixels = 0.0;
  int blockFinePixels = 16;     // side of the blocks tested for skipping
  bool skipUnreachable = true;  // false traces every ray (for checking the skipping)
};

struct SurveyGrid {
  int width = 101;  // survey pixels
  int height = 101;
  double pixelScaleArcsec = 0.257;  // survey pixel size
  // Position of the lens centre in 0-based survey pixel coordinates (pixel centres are integers).
  double lensXPix = 50.0;
  double lensYPix = 50.0;
};

struct SourcePlacement {
  Vec2 betaArcsec{0.0, 0.0};  // source-stamp centre on the source plane, relative to the lens
  double rotationRad = 0.0;   // stamp rotated counter-clockwise by this angle
  // Stamp pixel size on the sky; changing it resizes the source (resampling by the
  // interpolation). <= 0 means the stamp's own pixelScaleArcsec.
  double pixelScaleArcsec = 0.0;
};

struct RayTraceStats {
  long long raysTraced = 0;
  long long finePixelsSkipped = 0;
  long long finePixelsTotal = 0;
};

// Lensed image of the source on the survey grid, flux per survey pixel (same unit as the stamp).
// Throws ConfigError for non-positive scales, subSamples < 1 or an empty stamp.
ImageD traceLensedImage(const EllipticalPotentialLens& lens, const SourceStamp& source,
                        const SourcePlacement& placement, const SurveyGrid& grid,
                        const RayTraceOptions& options = {}, RayTraceStats* stats = nullptr);

// Flux-conserving rebinning: input pixels of inScaleArcsec and output pixels of outScaleArcsec
// share their lower-left corner (0-based pixel (0,0) edges coincide). Each output pixel receives
// each input pixel's flux times the fraction of the input pixel's area it overlaps. Flux that
// falls outside the output grid is lost; everything inside is kept exactly. Works for any ratio.
ImageD rebinFluxConserving(const ImageD& in, double inScaleArcsec, int outWidth, int outHeight,
                           double outScaleArcsec);

}  // namespace octarc::simulation
