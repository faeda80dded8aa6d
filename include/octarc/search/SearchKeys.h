// The configuration of `octarc search`: its keys (those of detect and the search's own), and
// the settings a loaded configuration gives.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "octarc/catalog/Catalog.h"
#include "octarc/lenslight/LensSubtraction.h"
#include "octarc/run/RunSettings.h"
#include "octarc/search/Inspection.h"
#include "octarc/search/Search.h"
#include "octarc/sexcompat/Assoc.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The configuration keys of `octarc search`: those of detect (run/RunKeys.h) and GRID_NAME,
// SEARCH_SPACE, MASK_NAME, MASK_BORDER, OUTPUT_DIR, SNR_MIN, RESOLVED_MIN, LENS_RADIUS,
// LENS_SIDE_ARCNESS, STAMP_SIZE, STAMP_PIXELS, STAMPS, NAME_PREFIX, the lens-light keys
// LENS_LIGHT, LENS_SELECT, LENS_CUTOUT, LENS_CHECKIMAGES, LENS_LIGHT_BAND, and the colour keys
// COLOUR_IMAGE, COLOUR_BAND, COLOUR_ZEROPOINT, COLOUR_SEEING_FWHM, COLOUR_CUT, DARK_PAIR_COLOUR.
std::vector<sexcompat::KeySpec> searchKeys();

struct SearchRunSettings {
  RunSettings run;                     // the image, weights, levels, columns (as for detect)
  std::string gridPath;                // GRID_NAME (SELECTION_METHOD GRID)
  std::string modelPath;               // MODEL_NAME (SELECTION_METHOD TREES)
  std::string maskPath;                // MASK_NAME, "" for none
  int borderPix = 0;                   // MASK_BORDER
  double maskPointRadiusArcsec = 0.0;  // MASK_POINT_RADIUS: a point of MASK_NAME masks this
                                       // circle (0: a point is an error)
  std::string inputCatalogPath;        // INPUT_CATALOG: its LDAC_OBJECTS instead of detecting
  std::string outputDir;               // OUTPUT_DIR
  // CATALOG_TYPE of OUTPUT_DIR/candidates.fits (the name is kept whatever the type; NONE is
  // refused, the candidates being the search's result).
  CatalogType catalogType = CatalogType::FitsLdac;
  SearchSettings search;  // pixelScaleArcsec set by the run (PIXEL_SCALE or the WCS)
  StampSettings stamps;
  bool writeStamps = true;   // STAMPS
  bool writeCutouts = true;  // STAMP_CUTOUTS (with STAMPS)
  // COLOUR_IMAGE: images of other bands on the measurement image's pixel grid, background-
  // subtracted as it is (without its weight map), their names in search.colourBands and their
  // zero-points (COLOUR_ZEROPOINT, else MAG_ZEROPOINT) here.
  std::vector<std::string> colourImagePaths;
  std::vector<double> colourZeropoints;
  // Their seeing FWHM (arcsec; COLOUR_SEEING_FWHM, else SEEING_FWHM), the Gaussian PSF of a lens
  // model fitted in one of them.
  std::vector<double> colourSeeingFwhmArcsec;
  // LENS_LIGHT_BAND: the index in colourImagePaths of the band the lens models are fitted in
  // (lenslight::FitBandImage), -1 for the searched image itself.
  int lensLightBand = -1;
  // ASSOC, when PARAMETERS_NAME asks for its columns (rows are never removed: the search needs
  // the whole component tree, so ASSOCSELEC_TYPE must be ALL).
  std::optional<sexcompat::AssocSettings> assoc;
  // LENS_LIGHT, LENS_SELECT, LENS_CUTOUT (search/LensLightSearch.h); the scale, seeing and
  // threads are the run's.
  lenslight::SubtractionSettings lensLight;
  bool lensCheckImages = true;  // LENS_CHECKIMAGES: lensmodel.fits and lensresidual.fits
};

// The settings of a loaded configuration; `run` is the detection part as the command line
// resolved it (image paths, PARAMETERS_NAME found). ConfigError for bad values (a SEARCH_SPACE
// without a name, ASSOCSELEC_TYPE other than ALL, as many COLOUR_BAND as COLOUR_IMAGE, ...).
SearchRunSettings searchSettingsFromConfig(const sexcompat::Config& config, RunSettings run);

}  // namespace octarc
