// The settings of one octarc run, read once from the configuration (defaults < .sex file <
// command line) and named with their units. Everything downstream reads this struct, never the
// raw configuration.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace octarc {

namespace sexcompat {
class Config;
}

enum class BackgroundType { Auto, Manual, Global };
enum class ThresholdType { Relative, Absolute };
// WEIGHT_TYPE; SExtractor's BACKGROUND (weights from the background RMS map) is not supported.
enum class WeightType { None, MapWeight, MapRms, MapVariance };

// The keys that, like SExtractor's, take a second value for the measurement image in dual-image
// mode (`octarc detect DETECT.fits,MEASURE.fits`); each is the first value when only one is
// given.
struct MeasurementImageSettings {
  BackgroundType backgroundType = BackgroundType::Auto;  // BACK_TYPE
  double backgroundValueAdu = 0.0;                       // BACK_VALUE
  WeightType weightType = WeightType::None;              // WEIGHT_TYPE
  std::string weightImagePath;                           // WEIGHT_IMAGE
  std::optional<double> weightThreshold;                 // WEIGHT_THRESH
};

struct RunSettings {
  // The image(s): one, or in dual-image mode the detection image then the measurement image
  // (same pixel grid). Footprints come from the first, photometry from the second.
  std::vector<std::string> imagePaths;
  std::string configPath;  // -c, or "" for the built-in defaults
  bool dualImage() const { return imagePaths.size() == 2; }
  const std::string& detectionImagePath() const { return imagePaths.front(); }
  const std::string& measurementImagePath() const { return imagePaths.back(); }

  std::string catalogType = "FITS_LDAC";
  std::vector<std::string> catalogNames{"test.cat"};
  std::string parametersPath = "default.param";

  // Detection and analysis thresholds: DETECT_THRESH / ANALYSIS_THRESH in THRESH_TYPE units.
  ThresholdType detectThresholdType = ThresholdType::Relative;
  ThresholdType analysisThresholdType = ThresholdType::Relative;
  double detectThreshold = 1.5;
  double analysisThreshold = 1.5;
  double detectThresholdMax = 20.0;  // DETECT_THRESH_MAX
  int detectLevelCount = 1;          // DETECT_NLEVELS
  std::vector<double> detectLevels;  // DETECT_LEVELS (explicit list), empty if not given
  int minAreaPix = 5;                // DETECT_MINAREA

  bool filter = true;
  std::string filterPath = "default.conv";

  BackgroundType backgroundType = BackgroundType::Auto;
  double backgroundValueAdu = 0.0;  // BACK_VALUE
  int backMeshWidthPix = 64, backMeshHeightPix = 64;
  int backFilterWidth = 3, backFilterHeight = 3;
  double backFilterThresholdAdu = 0.0;
  std::string backgroundMapPath;     // BACKGROUND_NAME (SExtractor BACKGROUND check-image)
  std::string backgroundRmsMapPath;  // BACKGROUND_RMS_NAME

  // Weight map (SEXTRACTOR.md section 4): a per-pixel variance for thresholds and FLUXERR_ISO.
  WeightType weightType = WeightType::None;  // WEIGHT_TYPE (first value)
  std::string weightImagePath;               // WEIGHT_IMAGE (first value)
  std::optional<double> weightThreshold;     // WEIGHT_THRESH in the map's units; unset = default
  bool rescaleWeights = true;                // RESCALE_WEIGHTS
  bool weightGain = true;                    // WEIGHT_GAIN
  // The measurement image's BACK_* and WEIGHT_* values (dual-image mode only).
  MeasurementImageSettings measurement;

  double magZeropoint = 0.0;
  double gainElectronPerAdu = 0.0;  // GAIN; 0 = infinite
  std::string gainKey = "GAIN";
  double saturationAdu = 50000.0;  // SATUR_LEVEL
  std::string saturationKey = "SATURATE";
  double pixelScaleArcsec = 0.0;  // PIXEL_SCALE (0 = from the WCS)
  double seeingFwhmArcsec = 1.2;

  std::vector<std::string> segmentationPaths;  // SEGMENTATION_NAME (measure)
  std::vector<std::string> inputCatalogPaths;  // INPUT_CATALOG (measure)
  bool appendColumns = true;  // APPEND_COLUMNS: with INPUT_CATALOG, append to each catalog (Y)
                              // or write one new catalog of every level (N)
  bool replaceInputCatalog = false;  // REPLACE_INPUT_CATALOG: CATALOG_NAME may be its input

  std::vector<std::string> checkImageTypes;  // CHECKIMAGE_TYPE (detect)
  std::vector<std::string> checkImageNames;  // CHECKIMAGE_NAME (detect)

  bool assoc = false;               // VECTOR_ASSOC or NUMBER_ASSOC requested (set later)
  bool quiet = false;               // VERBOSE_TYPE QUIET
  bool verboseFull = false;         // VERBOSE_TYPE FULL: also the time spent in each stage
  bool writeXml = false;            // WRITE_XML: SExtractor's XML run summary (catalog/RunXml.h)
  std::string xmlName = "sex.xml";  // XML_NAME
  std::string xslUrl;               // XSL_URL, named in the XML's prologue
  int threads = 0;                  // NTHREADS; 0 = all cores
};

// Reads every key octarc uses from a loaded configuration; ConfigError on inconsistent values.
// `weightMapsElsewhere`: the weight maps come from elsewhere (a batch's manifest), so that
// WEIGHT_TYPE without WEIGHT_IMAGE is no error (weightImagePath is left empty).
RunSettings settingsFromConfig(const sexcompat::Config& config, bool weightMapsElsewhere = false);

// The image arguments of a command line: one image, SExtractor's `DETECT,MEASURE` (a comma in a
// name that is not an existing file) or two names. Sets settings.imagePaths; a ConfigError when
// there are none or more than two, or when a dual-image run names BACKGROUND_NAME or
// BACKGROUND_RMS_NAME (those maps belong to one image).
void setImagePaths(RunSettings& settings, const std::vector<std::string>& arguments);

// The settings with which the measurement image of a dual-image run is read: its own BACK_* and
// WEIGHT_* values, no filter (the filter belongs to detection).
RunSettings measurementImageSettings(const RunSettings& settings);

// One input file of a run and the option that names it ("the image", "WEIGHT_IMAGE", ...).
struct NamedInput {
  std::string key;
  std::string path;
};
// Every file the run reads: the image(s), the -c file, PARAMETERS_NAME, FILTER_NAME (FILTER Y),
// WEIGHT_IMAGE, BACKGROUND_NAME, BACKGROUND_RMS_NAME, SEGMENTATION_NAME, INPUT_CATALOG and
// `assocListPath` when not empty. Outputs are checked against them (refuseOutputOverInput).
std::vector<NamedInput> runInputs(const RunSettings& settings, const std::string& assocListPath);

}  // namespace octarc
