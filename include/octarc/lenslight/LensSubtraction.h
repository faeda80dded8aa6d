// Lens-light subtraction over a whole image (METHOD.md section 5): the bright, smooth galaxies of
// a multi-threshold catalog chosen by an expression, a Sersic model fitted to each in a cut-out
// (SersicFit.h), the models added into one model image, and the objects detected again on the
// residual, so that an arc swallowed by its lens's halo at every threshold separates.
//
//   catalog (level-1 rows) --LENS_SELECT--> galaxies --fitLensLight, per cut-out--> model image
//     --> residual = image - model --> detected and measured again, the catalog's columns
//     --> the residual's rows near a fitted galaxy, which is their lens (residualRowsNearLenses)
//
// Positions in tables are 1-based pixels; cut-out corners and image indices are 0-based
// (core/Conventions.h). A fit that fails is recorded (FittedGalaxy::failure) and the galaxy is
// left in the image: per-galaxy trouble never stops a run.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Progress.h"
#include "octarc/core/Table.h"
#include "octarc/lenslight/SersicFit.h"

namespace octarc::lenslight {

// LENS_LIGHT: where the models are subtracted.
enum class SubtractionMode {
  Off,    // N
  Local,  // LOCAL: the image is searched as it is, plus the residual around each fitted galaxy
  Image,  // IMAGE: the search runs on the image with every model subtracted before detection
};

// "N", "LOCAL" or "IMAGE" (any case); ConfigError otherwise.
SubtractionMode parseSubtractionMode(const std::string& word);

struct SubtractionSettings {
  SubtractionMode mode = SubtractionMode::Off;
  // Which level-1 rows are fitted (selection/ColumnExpression.h), e.g. the default
  // "MAG_ISO < 20.5 && E_IMAGE < 0.5 && FLAGS < 4": bright, not very elongated galaxies, neither
  // saturated (a star's core) nor cut by the image border.
  std::string selectExpression = "MAG_ISO < 20.5 && E_IMAGE < 0.5 && FLAGS < 4";
  double cutoutArcsec = 20.0;  // side of the square modelled around each galaxy
  // Half the side of the square fitted, within the cut-out (0: the whole cut-out); the model is
  // drawn over the whole cut-out. A search fits out to 1" beyond its LENS_RADIUS: the arcs it
  // looks for lie inside, and the fit's cost goes with the pixels drawn.
  double fitHalfSideArcsec = 0.0;
  double pixelScaleArcsec = 0;  // > 0
  double seeingFwhmArcsec = 0;  // the model's Gaussian PSF; 0: none
  LensLightSettings fit;        // psfSigmaPix is set from the seeing
  int threads = 1;
  // The pre-screen (quickResidual below): a chosen galaxy is fitted only when the residual of a
  // cheap model of it holds an object of at least this S/N and this size (sqrt(2) SIZE_IMAGE)
  // between kMinLensArcArcsec and searchRadiusArcsec from its centre that the image does not
  // already separate; 0 fits every chosen galaxy. A search sets them to 3/4 of its SNR_MIN and
  // RESOLVED_MIN, below which no residual object makes a candidate (the margin: the search
  // measures the residual at lower thresholds), and the radius to its LENS_RADIUS.
  double prescreenMinSnr = 0.0;
  double prescreenMinSizeArcsec = 0.0;
  double searchRadiusArcsec = 6.0;
};

// LENSFIT_FLAGS, the bits of FittedGalaxy::failure. 1, 2, 4, 16 and 64 leave the galaxy in the
// image; 8 is a warning and 32 information, the model is subtracted.
enum FitFailure : int {
  kFitNotConverged = 1,   // the solver stopped without converging
  kFitOutsideCutout = 2,  // the fitted centre left the cut-out, or the radius ran to a limit
  kFitTooFewPixels = 4,   // fewer usable pixels than parameters (bad weights, an edge)
  kFitAtBound = 8,        // the index or the axis ratio ended on a bound (SersicFitSettings)
  kFitSkipped = 16,       // not fitted: its quick residual holds nothing to search (pre-screen)
  // Fitted in another band's image (FitBandImage, LENS_LIGHT_BAND), its flux scaled by the
  // galaxy's flux ratio in its core and drawn with this image's PSF: information, not trouble.
  kFitOtherBand = 32,
  // Fitted in another band, but no positive, finite flux ratio between the bands in its core
  // (no light there in this image, or no usable pixel): left in the image.
  kFitNoBandRatio = 64,
};
inline constexpr int kFitLeftInImage =
    kFitNotConverged | kFitOutsideCutout | kFitTooFewPixels | kFitSkipped | kFitNoBandRatio;

struct FittedGalaxy {
  // Its level-1 row in the searched catalog (LENS_LIGHT IMAGE: moved to the row appended for it
  // when subtracted; a failed galaxy's row is that of the image's catalog, which IMAGE drops).
  std::size_t row = 0;
  std::int32_t number = 0;      // and that row's NUMBER
  double xPix = 0, yPix = 0;    // the catalog's centroid, 1-based
  std::int64_t x0 = 0, y0 = 0;  // the cut-out's first pixel, 0-based
  std::int64_t width = 0, height = 0;
  SersicFitResult fit;  // centre in cut-out pixels (0-based); the start only when skipped
  int failure = 0;      // FitFailure bits (LENSFIT_FLAGS)
  // S/N of the brightest object of the pre-screen's quick residual that decided the fit (NaN:
  // no pre-screen, or nothing in the residual).
  double quickResidualSnr = std::numeric_limits<double>::quiet_NaN();
  // Fitted in another band (kFitOtherBand): this image's flux over that band's in the galaxy's
  // core (coreFluxRatio), by which `fit`'s flux and its error were scaled; NaN otherwise.
  double bandFluxRatio = std::numeric_limits<double>::quiet_NaN();
  bool fitted() const { return (failure & kFitSkipped) == 0; }
  bool subtracted() const { return (failure & kFitLeftInImage) == 0; }
  // The fitted centre as 1-based image pixels.
  double fittedXPix() const;
  double fittedYPix() const;
};

struct Subtraction {
  std::vector<FittedGalaxy> galaxies;  // in catalog row order
  ImageF model;                        // every subtracted galaxy's model (ADU), image-sized
  ImageF residual;                     // pixels - model
  std::int64_t subtractedCount() const;
  std::int64_t fittedCount() const;  // not skipped by the pre-screen
};

// Another band's image on the searched image's pixel grid, in which the galaxies are fitted
// instead (LENS_LIGHT_BAND): a redder band, where the lens dominates and a blue arc is faint, so
// that the arc does not pull the model. Each galaxy is chosen and pre-screened in the searched
// image, fitted in this one's cut-out (same pixels) with this one's PSF, and its model is drawn
// with the searched image's PSF (for Gaussian PSFs, the sharper band's model convolved with a
// Gaussian of sqrt(sigma_broad^2 - sigma_sharp^2): PSF-matched either way) and scaled by the
// galaxy's flux ratio between the bands in its core (coreFluxRatio), where an arc adds little.
struct FitBandImage {
  const ImageF* pixels = nullptr;        // background-subtracted, the searched image's size
  const ImageF* varianceAdu2 = nullptr;  // per-pixel variances; null or empty: sigmaAdu^2
  double sigmaAdu = 0.0;
  double seeingFwhmArcsec = 0.0;  // its Gaussian PSF; 0: none
};

// Radius of the core in which the flux ratio between the bands is measured: well inside
// kMinLensArcArcsec, the closest an arc lies to its lens, so that an arc's light reaches it only
// through the seeing's wings (which still add to it: an arc of 0.375 times the lens's flux at
// 1.5" in 1" seeing raises the ratio by 1.5 %); at least kBandRatioCoreMinPix, so that a coarse
// pixel grid still has a few pixels in it.
inline constexpr double kBandRatioCoreArcsec = 0.3;
inline constexpr double kBandRatioCoreMinPix = 1.5;

// The least-squares amplitude of `model` in `stamp` over the pixels within radiusPix of
// (xPix, yPix) (0-based) with a usable variance: sum(d m / v) / sum(m^2 / v). With `model` a
// galaxy's model fitted in another band and drawn with this image's PSF, it is this image's flux
// over that band's. NaN when no such pixel holds model light.
double coreFluxRatio(const ImageD& stamp, const ImageD& varianceAdu2, const ImageD& model,
                     double xPix, double yPix, double radiusPix);

// ConfigError when `catalog` lacks a column subtractLensLight needs (X_IMAGE, Y_IMAGE,
// THRESH_LEVEL, NUMBER and the expression's): a catalog with no rows, the planned columns,
// checks a run before its detection.
void checkLensSelectColumns(const Table& catalog, const std::string& selectExpression);

// The pre-screen's cheap model of a galaxy in `stamp`: the medians of the pixels in elliptical
// annuli 1 px wide, linear between them, about (xPix, yPix) (0-based), shaped by the second moments
// of the positive pixels within shapeRadiusPix of it (a median, so that an arc covering part of an
// annulus stays in the residual; an arc or ring filling most of an annulus does not, which is why
// the fit is robust). Its residual, smoothed on 3 x 3 pixels, is cut at 3 sigma outside a core of
// 0.8 minRadiusPix (where the annuli miss the cusp, and an arc near it would join that piece);
// the 8-connected pieces whose centroid lies between minRadiusPix and maxRadiusPix from the
// centre are the objects, with S/N = sum / sqrt(sum of variances) (sky noise only).
struct QuickResidualObject {
  double xPix = 0, yPix = 0;  // centroid, 0-based stamp pixels
  double fluxAdu = 0, snr = 0;
  double sizePix = 0;  // sqrt(Ixx + Iyy) of its positive residual, as SIZE_IMAGE
};
std::vector<QuickResidualObject> quickResidual(const ImageD& stamp, const ImageD& varianceAdu2,
                                               double xPix, double yPix, double shapeRadiusPix,
                                               double minRadiusPix, double maxRadiusPix);

// Chooses the galaxies among the level-1 rows of `catalog` (X_IMAGE, Y_IMAGE, THRESH_LEVEL and
// the expression's columns; FLUX_ISO, when there, for the pre-screen), pre-screens each
// (SubtractionSettings::prescreenMinSnr: an object of the quick residual with no row of the
// catalog within 0.5" of it holding at least half its flux, i.e. not one the image already
// separates), fits each in its cut-out of `pixels` (background-subtracted) with
// per-pixel variances `varianceAdu2` (a weight map's; empty: sigmaAdu^2 everywhere), on
// `settings.threads` threads, and builds the model and residual images. With `fitBand`, each
// galaxy is fitted in that band's image instead and its model scaled and PSF-matched to this one
// (FitBandImage). ConfigError for a bad expression or settings, or a fitBand image of another
// size; `progress` hears of each galaxy.
Subtraction subtractLensLight(const ImageF& pixels, const ImageF& varianceAdu2, double sigmaAdu,
                              const Table& catalog, const SubtractionSettings& settings,
                              const ProgressFn& progress = {},
                              const FitBandImage* fitBand = nullptr);

// An arc is at least this far from its lens's centre (METHOD.md section 3): residual objects
// closer are what is left of the galaxy itself.
inline constexpr double kMinLensArcArcsec = 1.0;

// The rows of a catalog measured on the residual that belong to a fitted galaxy: centroid
// within `radiusArcsec` of its fitted centre and at least kMinLensArcArcsec from it (the
// nearest subtracted galaxy when several qualify).
struct ResidualRows {
  std::vector<std::int64_t> rows;   // in the residual catalog
  std::vector<std::size_t> galaxy;  // per row: index into Subtraction::galaxies
};
ResidualRows residualRowsNearLenses(const Table& residualCatalog, const Subtraction& subtraction,
                                    double radiusArcsec, double pixelScaleArcsec);

}  // namespace octarc::lenslight
