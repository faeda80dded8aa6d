// One image extension made ready for measurement: pixels read, background subtracted, noise
// known, detection image filtered, WCS and photometric settings resolved.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/measure/MeasureContext.h"

namespace octarc {

struct RunSettings;

// Where the background level and noise came from; written to the catalog header (OCTBKSRC).
struct NoiseOrigin {
  std::string background;  // "MANUAL", "AUTO", "GLOBAL", "CATALOG", "CHECKIMAGE"
  std::string sigma;       // "MESH_MEDIAN", "CLIPPED_RMS", "CATALOG", "CHECKIMAGE"
};

// Values that an input SExtractor catalog's LDAC_IMHEAD fixes for the run (SEXBKGND etc.).
struct CatalogRunValues {
  std::optional<double> backgroundAdu;  // SEXBKGND
  std::optional<double> sigmaAdu;       // SEXBKDEV
  std::optional<double> gain;           // SEXGAIN
  std::optional<double> thresholdAdu;   // SEXTHLD
  std::optional<double> analysisThresholdAdu;  // SEXATHLD
};

struct PreparedImage {
  ImageHdu hdu;              // pixels: background-subtracted measurement image
  ImageF filtered;           // filtered detection image; empty when FILTER N
  std::optional<ImageF> backgroundMap;     // background map, kept only for check images
  std::optional<ImageF> backgroundRmsMap;  // per-pixel RMS, kept only for check images
  double backgroundAdu = 0.0;  // constant (or global) background level
  double sigmaAdu = 0.0;       // global noise sigma
  double gain = 0.0;
  double saturationAdu = 0.0;
  std::vector<std::int64_t> saturatedPixels;  // raw value >= saturationAdu, ascending
  NoiseOrigin origin;
  std::vector<std::string> warnings;  // non-fatal notes (constant image, bad meshes, ...)
  std::optional<Wcs> wcs;

  const ImageF& detectionImage() const { return filtered.empty() ? hdu.pixels : filtered; }
  // The measurement context for this image (levels to be filled by the caller).
  MeasureContext context(const RunSettings& settings) const;
};

// Reads `imagePath` and resolves background, noise, gain, saturation, filter and WCS following
// SExtractor's rules and octarc's order of precedence (README, "Background and noise").
// `keepCheckMaps` keeps full background/RMS maps for BACKGROUND check images.
PreparedImage prepareImage(const std::string& imagePath, const RunSettings& settings,
                           const CatalogRunValues& fromCatalog, bool keepCheckMaps);

// Converts a threshold in THRESH_TYPE units to ADU (RELATIVE: multiples of sigma).
double thresholdToAdu(double value, bool relative, double sigmaAdu);

}  // namespace octarc
