// One image extension made ready for measurement: pixels read, background subtracted, noise
// known, detection image filtered, WCS and photometric settings resolved.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "octarc/background/MeshBackground.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/ConvKernel.h"
#include "octarc/core/Image.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/measure/MeasureContext.h"
#include "octarc/run/RunSettings.h"

namespace octarc {

// Where the background level and noise came from; written to the catalog header (OCTBKSRC).
struct NoiseOrigin {
  std::string background;  // "MANUAL", "AUTO", "GLOBAL", "CATALOG", "CHECKIMAGE"
  std::string sigma;       // "MESH_MEDIAN", "CLIPPED_RMS", "CATALOG", "CHECKIMAGE"
};

// Values that an input SExtractor catalog's LDAC_IMHEAD fixes for the run (SEXBKGND etc.).
struct CatalogRunValues {
  std::optional<double> backgroundAdu;         // SEXBKGND
  std::optional<double> sigmaAdu;              // SEXBKDEV
  std::optional<double> gain;                  // SEXGAIN
  std::optional<double> thresholdAdu;          // SEXTHLD
  std::optional<double> analysisThresholdAdu;  // SEXATHLD
};

// The run values of one part of an input catalog, from its LDAC_IMHEAD. A keyword that is
// absent leaves its value unset; one that is present but not a finite number, or out of range
// (SEXBKDEV <= 0, SEXGAIN < 0, SEXTHLD or SEXATHLD <= 0), is an IoError naming `catalogPath`
// and the keyword and quoting the value: octarc would otherwise measure with a background,
// noise or gain that SExtractor cannot have used.
CatalogRunValues catalogRunValues(const InputCatalogPart& part, const std::string& catalogPath);

// The value of header keyword `key` when it is a finite number >= 0 (a gain, a saturation
// level). A keyword that is absent gives nullopt; one that is present with another value is
// ignored, also nullopt, with a warning naming `imagePath`, the keyword and its value, and
// saying what is used instead (`instead`, e.g. "GAIN 4 of the configuration").
std::optional<double> headerNonNegative(const FitsHeader& header, const std::string& key,
                                        const std::string& imagePath, const std::string& instead,
                                        std::vector<std::string>& warnings);

struct PreparedImage {
  ImageHdu hdu;     // pixels: background-subtracted measurement image
  ImageF filtered;  // filtered detection image; empty when FILTER N
  // BACKGROUND_NAME / BACKGROUND_RMS_NAME maps read from files, kept only for check images.
  std::optional<ImageF> backgroundMap;
  std::optional<ImageF> backgroundRmsMap;
  // The mesh background when one was estimated (a few grids, not image-sized): check images
  // are interpolated from it on demand.
  std::optional<MeshBackground> mesh;
  // The weight map's pixels again, for reloadVariance, when they came from memory rather than
  // from WEIGHT_IMAGE (ImageMaps::weights); empty otherwise.
  std::function<ImageF()> weightReader;
  // Per-pixel variance (ADU^2) from WEIGHT_IMAGE; empty without a weight map. Pixels that
  // WEIGHT_THRESH rejects (zero weight by default), or NaN weights, hold +Inf: they never join an
  // object and are left out of every measurement sum.
  ImageF variance;
  // True when `variance` holds the variance filtered by the detection filter (prepareImage
  // with filterVariance): what the detection thresholds follow, not what measurements use.
  bool varianceFiltered = false;
  double weightScale = 1.0;    // RESCALE_WEIGHTS factor of `variance` (1 without weights)
  double backgroundAdu = 0.0;  // constant (or global) background level
  double sigmaAdu = 0.0;       // global noise sigma
  double gain = 0.0;
  double saturationAdu = 0.0;
  std::vector<std::int64_t> saturatedPixels;  // raw value >= saturationAdu, ascending
  NoiseOrigin origin;
  std::vector<std::string> warnings;  // non-fatal notes (constant image, bad meshes, ...)
  std::optional<Wcs> wcs;

  // Dual-image mode (prepareDualImage): `filtered` holds the detection image (filtered or not)
  // and `hdu`, `variance` and the values above are the measurement image's; the detection
  // image's noise and variance, which set the thresholds, are kept apart here.
  bool separateDetection = false;
  double detectionSigmaAdu = 0.0;
  double detectionWeightScale = 1.0;
  // The detection image's variance (filtered with filterVariance); empty without its weights.
  ImageF detectionVariance;

  const ImageF& detectionImage() const { return filtered.empty() ? hdu.pixels : filtered; }
  // The noise sigma the RELATIVE thresholds are in units of.
  double detectionSigma() const { return separateDetection ? detectionSigmaAdu : sigmaAdu; }
  // The variance the per-pixel thresholds follow: the detection image's own in dual-image mode.
  ImageF& thresholdVariance() { return separateDetection ? detectionVariance : variance; }
  // The BACKGROUND and BACKGROUND_RMS check images (SExtractor's: the interpolated mesh maps
  // for BACK_TYPE AUTO, constants otherwise). With a weight map, source-extractor 2.25 still
  // writes the interpolated mesh RMS (of the weighted mesh statistics), not sqrt(variance).
  ImageF backgroundImage() const;
  ImageF backgroundRmsImage() const;
  // Replaces a filtered `variance` by the unfiltered one, read again from WEIGHT_IMAGE (the
  // filtered buffer is freed first, so only one exists at a time). No-op otherwise.
  void reloadVariance(const RunSettings& settings);
  // The measurement context for this image (levels to be filled by the caller).
  MeasureContext context(const RunSettings& settings) const;
  MeasureContext context(double magZeropoint, double pixelScaleArcsec) const;
};

// Reads `imagePath` and resolves background, noise, gain, saturation, filter and WCS following
// SExtractor's rules and octarc's order of precedence (README, "Background and noise").
// `keepCheckMaps` keeps the BACKGROUND_NAME / BACKGROUND_RMS_NAME maps read from files for
// check images. With WEIGHT_TYPE MAP_WEIGHT / MAP_RMS / MAP_VAR the weight map (IoError naming it
// when its size differs from the image's) enters the mesh background and becomes `variance`.
// `filterVariance` (octarc detect, FILTER Y): `variance` is the variance filtered by the
// detection filter, as SExtractor's per-pixel thresholds use it (see reloadVariance).
PreparedImage prepareImage(const std::string& imagePath, const RunSettings& settings,
                           const CatalogRunValues& fromCatalog, bool keepCheckMaps,
                           bool filterVariance = false);

// Maps given in memory (the Python module's arrays) instead of the files the settings name.
// Each is a function returning the map's pixels, the image's size (IoError naming the map
// otherwise); the weights may be asked for twice (reloadVariance), so a reader must make them
// anew each time. An empty function: the file of the settings, if any.
struct ImageMaps {
  std::function<ImageF()> weights;     // in place of WEIGHT_IMAGE (WEIGHT_TYPE says what they are)
  std::function<ImageF()> background;  // in place of BACKGROUND_NAME
  const ConvKernel* filter = nullptr;  // in place of FILTER_NAME (with FILTER Y)
};

// prepareImage for an image already in memory: `image` (its pixels moved in; its header gives
// GAIN, SATURATE and the WCS as a file's would), named `imageName` in messages, with `maps`
// standing in for the settings' WEIGHT_IMAGE, BACKGROUND_NAME and FILTER_NAME, and `given`
// values (a known noise sigma...) as an input catalog's. The same steps, in the same order and
// arithmetic, as for a file.
PreparedImage prepareImage(ImageHdu image, const std::string& imageName,
                           const RunSettings& settings, const ImageMaps& maps,
                           const CatalogRunValues& given, bool filterVariance = false);

// Why two images are not on one pixel grid, "" when they are: their sizes differ ("WxH and WxH
// pixels"), or both have a celestial WCS and a corner pixel of one lands more than 0.1 pixel
// from the same corner of the other.
std::string pixelGridDifference(std::int64_t widthA, std::int64_t heightA,
                                const std::optional<Wcs>& wcsA, std::int64_t widthB,
                                std::int64_t heightB, const std::optional<Wcs>& wcsB);

// Dual-image mode: `detectionPath` prepared with `settings` (its filter, BACK_* and WEIGHT_*
// first values) for detection, `measurementPath` with measurementImageSettings(settings) for the
// measurements, both on the same pixel grid: an IoError naming both when their sizes differ, or
// when both have a celestial WCS and a corner of one lands more than 0.1 pixel from the same
// corner of the other. Gain, saturation, WCS and header come from the measurement image, as in
// SExtractor.
PreparedImage prepareDualImage(const std::string& detectionPath, const std::string& measurementPath,
                               const RunSettings& settings, bool keepCheckMaps,
                               bool filterVariance = false);

// The image extension `e` of `count` of the run, prepared for detection and measurement: one
// image (prepareImage) or, in dual-image mode, the detection and measurement pair.
PreparedImage prepareRunImage(const RunSettings& settings, int e, int count, bool keepCheckMaps,
                              bool filterVariance);

// The path of extension `e` (0-based, among `count` image extensions) of a file that must have
// as many image extensions as the measured image, like SExtractor's check-images and weight
// maps of a multi-extension image; the path itself when count is 1. IoError naming `what`.
std::string extensionPath(const std::string& path, int e, int count, const char* what);

// The settings for extension `e` of `count`: the per-image inputs (the images, BACKGROUND_NAME,
// BACKGROUND_RMS_NAME, WEIGHT_IMAGE) point at their own extension `e`.
RunSettings settingsForExtension(const RunSettings& settings, int e, int count);

// The pixels of `raw` at or above `levelAdu` (ascending linear indices), found on `threads`
// threads; none when levelAdu <= 0. SATUR_LEVEL applies to raw values: call it before the
// background is subtracted.
std::vector<std::int64_t> findSaturatedPixels(const ImageF& raw, double levelAdu, int threads);

// A FILTER_NAME given without a directory and absent from the working directory is looked up,
// as a convenience, in octarc's data directory (core/DataFiles.h) and then in Debian's
// source-extractor share directory; found nowhere, IoError naming the three places.
std::string resolveFilterFile(const std::string& path);

}  // namespace octarc
