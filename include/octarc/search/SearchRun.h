// A whole search of one image, as `octarc search` (and a batch of tiles) runs it:
//
//   image (+ weight map) --> prepared once (run/PreparedImage.h)
//     --> rows: detected and measured in memory (run/DetectionRun.h), or INPUT_CATALOG
//     --> searched area: MASK_NAME regions, bad weights, MASK_BORDER (selection/SearchMask.h)
//     --> grid (GRID_NAME) checked against the image's setup (a warning when they differ)
//     --> candidates (search/Search.h)
//   --> writeSearchOutputs(): OUTPUT_DIR holding candidates.fits (CATALOG_TYPE, FITS-LDAC by
//       default), candidates.cat (ASCII_HEAD), candidates.reg (DS9), stamps/NNNN.png (with
//       COLOUR_IMAGE also stamps/NNNN.colour.png), index.html
//       (the vetting page), summary.txt and, with LENS_LIGHT, lensfit.fits (the fitted galaxies)
//       and the check-images lensmodel.fits and lensresidual.fits, written whole into a temporary
//       directory and renamed into place.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "octarc/catalog/Catalog.h"
#include "octarc/core/Progress.h"
#include "octarc/core/Table.h"
#include "octarc/io/Ds9Region.h"
#include "octarc/lenslight/LensSubtraction.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunSettings.h"
#include "octarc/search/Inspection.h"
#include "octarc/search/Search.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/selection/GridFile.h"
#include "octarc/sexcompat/Assoc.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The file that marks a directory as a search output, written last: an existing OUTPUT_DIR is
// replaced only when it holds it (a user's directory that merely holds a candidates.fits is
// refused), and its content is checked too.
inline constexpr const char* kSearchMarkerFile = ".octarc-search";
inline constexpr const char* kSearchMarkerText = "octarc search output directory\n";

struct SearchRun {
  PreparedImage image;  // the measurement image (background-subtracted) and its WCS
  Table catalog;        // every row of every level
  std::optional<SegmentationRuns> footprints;  // when detected here
  std::vector<ThresholdLevel> levels;
  std::optional<SavedGrid> grid;        // GRID_NAME, with SELECTION_METHOD GRID
  std::optional<SavedLensModel> model;  // MODEL_NAME, with SELECTION_METHOD TREES
  SearchResult result;
  double pixelScaleArcsec = 0.0;
  std::vector<std::string> warnings;       // grid made for another setup, no WCS, ...
  std::vector<std::string> runCards;       // the detection run's LDAC_IMHEAD cards
  std::vector<std::int64_t> catalogOrder;  // rows in catalog order (empty: as stored)
  // Searched pixels per SearchMask::kAreaBlockPix block (the union of a batch's tiles).
  Image<std::int32_t> searchedBlocks;
  // LENS_LIGHT: the fitted galaxies, model and residual images; per catalog row its lens-light
  // origin (SearchInput::lensLightOf); the residual rows near a fitted galaxy.
  std::optional<lenslight::Subtraction> lensLight;
  std::vector<std::int64_t> lensLightOf;
  std::int64_t lensLightRows = 0;
  // Per fitted galaxy, its NUMBER at level 1 of the searched catalog, which the candidates'
  // LENS_NUMBER refers to: the image's in LOCAL, the one appended past the residual's in IMAGE;
  // 0 when it is not in that catalog (IMAGE, a fit that failed).
  std::vector<std::int32_t> lensNumbers;
  // With COLOUR_IMAGE and STAMPS Y: each colour band's image as the colours were measured on it
  // (background-subtracted), kept for the colour stamps.
  std::vector<PreparedImage> colourImages;
};

// Runs the search. Before any pixel is read: the grid and the region file are read, OUTPUT_DIR
// is checked (a directory that is not an earlier search output is refused), no input may
// lie inside it (it is replaced whole) and each COLOUR_IMAGE must be on the measurement image's
// pixel grid (a ConfigError naming both). ConfigError / IoError on bad settings or input; nothing
// is written.
SearchRun searchImage(const SearchRunSettings& settings, const RunLog& log);

// A search of an image prepared in memory, as searchImage searches a file (the Python module's
// octarc.search): `image` detected and measured at every level of settings.run with its
// PARAMETERS_NAME columns (ASSOC as in a file's run), LENS_LIGHT applied, then the selection with
// `grid` or `model`, the one settings.search.method asks for (read by the caller, e.g. with
// loadGrid). COLOUR_IMAGE, MASK_NAME and INPUT_CATALOG name files and are refused here
// (ConfigError), as is a missing grid or model. `checkpoint` is called as
// DetectionRequest::checkpoint is (run/ImageRun.h). Nothing is written.
SearchRun searchPreparedImage(const SearchRunSettings& settings, PreparedImage image,
                              std::optional<SavedGrid> grid, std::optional<SavedLensModel> model,
                              const std::function<void()>& checkpoint, const RunLog& log);

// The candidates' table as OUTPUT_DIR/candidates.fits holds it (LDAC_OBJECTS, the summary in
// its keywords: search/CandidateTable.h).
FitsTable searchCandidateTable(const SearchRun& run, const SearchRunSettings& settings);

// The shapes of the DS9 region file `maskPath` (MASK_NAME, or a batch tile's mask) on the image
// `imagePath`, its points circles of MASK_POINT_RADIUS (pixels through PIXEL_SCALE, or the
// image's WCS when PIXEL_SCALE is 0). ConfigError / IoError as readDs9Regions.
std::vector<RegionShape> readSearchMask(const SearchRunSettings& settings,
                                        const std::string& maskPath, const std::string& imagePath);

// One report space's line of a summary: "  NAME (cut): N candidate(s), D per deg2" (without the
// density when there is no area).
std::string reportSpaceLine(const std::string& name, const std::string& expression,
                            std::int64_t candidates, double areaDeg2);

// The summary lines (printed, in summary.txt and on the vetting page).
std::vector<std::string> searchSummaryLines(const SearchRun& run,
                                            const SearchRunSettings& settings);

// Writes OUTPUT_DIR whole (see above); `progress` is told of each stamp. `addFiles`, when given,
// writes files of the caller's into the directory (its temporary path) before it is marked
// complete. IoError naming the directory on failure, which leaves no partial directory.
void writeSearchOutputs(const SearchRun& run, const SearchRunSettings& settings,
                        const ProgressFn& progress, const RunLog& log,
                        const std::function<void(const std::string& dir)>& addFiles = {});

}  // namespace octarc
