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
  double cutoutArcsec = 20.0;   // side of the square fitted around each galaxy
  double pixelScaleArcsec = 0;  // > 0
  double seeingFwhmArcsec = 0;  // the model's Gaussian PSF; 0: none
  LensLightSettings fit;        // psfSigmaPix is set from the seeing
  int threads = 1;
};

// Why a galaxy was left in the image (FittedGalaxy::failure), as bits of LENSFIT_FLAGS.
enum FitFailure : int {
  kFitNotConverged = 1,   // the solver stopped without converging
  kFitOutsideCutout = 2,  // the fitted centre left the cut-out, or the radius ran to a limit
  kFitTooFewPixels = 4,   // fewer usable pixels than parameters (bad weights, an edge)
};

struct FittedGalaxy {
  // Its level-1 row in the searched catalog (LENS_LIGHT IMAGE: moved to the row appended for it
  // when subtracted; a failed galaxy's row is that of the image's catalog, which IMAGE drops).
  std::size_t row = 0;
  std::int32_t number = 0;      // and that row's NUMBER
  double xPix = 0, yPix = 0;    // the catalog's centroid, 1-based
  std::int64_t x0 = 0, y0 = 0;  // the cut-out's first pixel, 0-based
  std::int64_t width = 0, height = 0;
  SersicFitResult fit;  // centre in cut-out pixels (0-based)
  int failure = 0;      // FitFailure bits; 0: subtracted
  bool subtracted() const { return failure == 0; }
  // The fitted centre as 1-based image pixels.
  double fittedXPix() const;
  double fittedYPix() const;
};

struct Subtraction {
  std::vector<FittedGalaxy> galaxies;  // in catalog row order
  ImageF model;                        // every subtracted galaxy's model (ADU), image-sized
  ImageF residual;                     // pixels - model
  std::int64_t subtractedCount() const;
};

// ConfigError when `catalog` lacks a column subtractLensLight needs (X_IMAGE, Y_IMAGE,
// THRESH_LEVEL, NUMBER and the expression's): a catalog with no rows, the planned columns,
// checks a run before its detection.
void checkLensSelectColumns(const Table& catalog, const std::string& selectExpression);

// Chooses the galaxies among the level-1 rows of `catalog` (X_IMAGE, Y_IMAGE, THRESH_LEVEL and
// the expression's columns), fits each in its cut-out of `pixels` (background-subtracted) with
// per-pixel variances `varianceAdu2` (a weight map's; empty: sigmaAdu^2 everywhere), on
// `settings.threads` threads, and builds the model and residual images. ConfigError for a bad
// expression or settings; `progress` hears of each galaxy.
Subtraction subtractLensLight(const ImageF& pixels, const ImageF& varianceAdu2, double sigmaAdu,
                              const Table& catalog, const SubtractionSettings& settings,
                              const ProgressFn& progress = {});

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
