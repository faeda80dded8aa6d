#include "octarc/run/RunSettings.h"

#include <algorithm>
#include <cctype>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

namespace {

ThresholdType thresholdType(const std::string& keyword) {
  return uppercase(keyword) == "ABSOLUTE" ? ThresholdType::Absolute : ThresholdType::Relative;
}

// The second value of a key that takes (detection, measurement) pairs like SExtractor's
// BACK_VALUE and THRESH_TYPE, or the first when only one is given. Every list is read through
// the Config getters, which report a missing value as a ConfigError naming the key.
std::string secondOrFirst(const sexcompat::Config& config, const char* key) {
  return config.getString(key, config.count(key) > 1 ? 1 : 0);
}

}  // namespace

RunSettings settingsFromConfig(const sexcompat::Config& config, bool weightMapsElsewhere) {
  RunSettings s;
  s.catalogType = uppercase(config.getString("CATALOG_TYPE"));
  s.catalogNames = config.getStrings("CATALOG_NAME");
  s.parametersPath = config.getString("PARAMETERS_NAME");

  s.detectThresholdType = thresholdType(config.getString("THRESH_TYPE", 0));
  s.analysisThresholdType = thresholdType(secondOrFirst(config, "THRESH_TYPE"));
  s.detectThreshold = config.getDouble("DETECT_THRESH");
  s.analysisThreshold = config.getDouble("ANALYSIS_THRESH");
  if (config.getDoubles("DETECT_THRESH").size() > 1 ||
      config.getDoubles("ANALYSIS_THRESH").size() > 1) {
    throw ConfigError(
        "DETECT_THRESH/ANALYSIS_THRESH: surface-brightness thresholds (mu,ZP) are not supported; "
        "give one value");
  }
  s.detectThresholdMax = config.getDouble("DETECT_THRESH_MAX");
  s.detectLevelCount = config.getInt("DETECT_NLEVELS");
  if (config.isExplicit("DETECT_LEVELS")) s.detectLevels = config.getDoubles("DETECT_LEVELS");
  s.minAreaPix = config.getInt("DETECT_MINAREA");

  s.filter = config.getBool("FILTER");
  s.filterPath = config.getString("FILTER_NAME");

  const std::string backType = uppercase(config.getString("BACK_TYPE", 0));
  s.backgroundType = backType == "MANUAL"   ? BackgroundType::Manual
                     : backType == "GLOBAL" ? BackgroundType::Global
                                            : BackgroundType::Auto;
  s.backgroundValueAdu = config.getDouble("BACK_VALUE", 0);
  s.backMeshWidthPix = config.getInt("BACK_SIZE", 0);
  s.backMeshHeightPix = config.getInt("BACK_SIZE", config.count("BACK_SIZE") > 1 ? 1 : 0);
  s.backFilterWidth = config.getInt("BACK_FILTERSIZE", 0);
  s.backFilterHeight =
      config.getInt("BACK_FILTERSIZE", config.count("BACK_FILTERSIZE") > 1 ? 1 : 0);
  s.backFilterThresholdAdu = config.getDouble("BACK_FILTTHRESH");
  // The optional file names and lists may be set to nothing (as the -d/-dd dumps write them):
  // that is the same as not setting them.
  if (config.count("BACKGROUND_NAME") > 0)
    s.backgroundMapPath = config.getString("BACKGROUND_NAME");
  if (config.count("BACKGROUND_RMS_NAME") > 0) {
    s.backgroundRmsMapPath = config.getString("BACKGROUND_RMS_NAME");
  }

  // A bare WEIGHT_TYPE keeps the default, NONE (Config: an empty list is "not given").
  const std::string weightType = uppercase(config.getString("WEIGHT_TYPE", 0));
  if (weightType == "BACKGROUND") {
    throw ConfigError(
        "WEIGHT_TYPE BACKGROUND is not supported; give a map with MAP_WEIGHT, MAP_RMS or MAP_VAR");
  }
  s.weightType = weightType == "MAP_WEIGHT" ? WeightType::MapWeight
                 : weightType == "MAP_RMS"  ? WeightType::MapRms
                 : weightType == "MAP_VAR"  ? WeightType::MapVariance
                                            : WeightType::None;
  if (s.weightType != WeightType::None && !weightMapsElsewhere) {
    if (!config.isExplicit("WEIGHT_IMAGE")) {
      throw ConfigError("WEIGHT_IMAGE: WEIGHT_TYPE " + weightType + " needs a weight map file");
    }
    s.weightImagePath = config.getString("WEIGHT_IMAGE", 0);
  }
  if (config.isExplicit("WEIGHT_THRESH")) s.weightThreshold = config.getDouble("WEIGHT_THRESH", 0);
  s.rescaleWeights = config.getBool("RESCALE_WEIGHTS");
  s.weightGain = config.getBool("WEIGHT_GAIN");
  if (s.weightType != WeightType::None && !s.weightGain) {
    // The measurement module weights the Poisson term per pixel (SExtractor's WEIGHT_GAIN Y).
    throw ConfigError("WEIGHT_GAIN N is not supported; use WEIGHT_GAIN Y");
  }

  s.magZeropoint = config.getDouble("MAG_ZEROPOINT");
  s.gainElectronPerAdu = config.getDouble("GAIN");
  s.gainKey = config.getString("GAIN_KEY");
  s.saturationAdu = config.getDouble("SATUR_LEVEL");
  s.saturationKey = config.getString("SATUR_KEY");
  s.pixelScaleArcsec = config.getDouble("PIXEL_SCALE");
  s.seeingFwhmArcsec = config.getDouble("SEEING_FWHM");

  if (config.isExplicit("SEGMENTATION_NAME")) {
    s.segmentationPaths = config.getStrings("SEGMENTATION_NAME");
  }
  if (config.isExplicit("INPUT_CATALOG")) s.inputCatalogPaths = config.getStrings("INPUT_CATALOG");
  s.appendColumns = config.getBool("APPEND_COLUMNS");
  s.replaceInputCatalog = config.getBool("REPLACE_INPUT_CATALOG");

  for (const std::string& t : config.getStrings("CHECKIMAGE_TYPE")) {
    if (uppercase(t) != "NONE") s.checkImageTypes.push_back(uppercase(t));
  }
  if (!s.checkImageTypes.empty()) s.checkImageNames = config.getStrings("CHECKIMAGE_NAME");
  if (s.checkImageTypes.size() != s.checkImageNames.size()) {
    throw ConfigError("CHECKIMAGE_TYPE and CHECKIMAGE_NAME must list the same number of items");
  }

  if (config.getBool("FITS_UNSIGNED")) {
    throw ConfigError(
        "FITS_UNSIGNED Y is not supported: octarc reads FITS integers as signed, as "
        "the FITS standard (and SExtractor's default N) do");
  }

  s.quiet = uppercase(config.getString("VERBOSE_TYPE")) == "QUIET";
  s.verboseFull = uppercase(config.getString("VERBOSE_TYPE")) == "FULL";
  s.threads = config.getInt("NTHREADS");
  return s;
}

std::vector<NamedInput> runInputs(const RunSettings& s, const std::string& assocListPath) {
  std::vector<NamedInput> inputs;
  for (const std::string& p : s.imagePaths) inputs.push_back({"image", p});
  if (!s.configPath.empty()) inputs.push_back({"configuration file", s.configPath});
  inputs.push_back({"PARAMETERS_NAME", s.parametersPath});
  if (s.filter) inputs.push_back({"FILTER_NAME", s.filterPath});
  if (!s.weightImagePath.empty()) inputs.push_back({"WEIGHT_IMAGE", s.weightImagePath});
  if (!s.backgroundMapPath.empty()) inputs.push_back({"BACKGROUND_NAME", s.backgroundMapPath});
  if (!s.backgroundRmsMapPath.empty()) {
    inputs.push_back({"BACKGROUND_RMS_NAME", s.backgroundRmsMapPath});
  }
  for (const std::string& p : s.segmentationPaths) inputs.push_back({"SEGMENTATION_NAME", p});
  for (const std::string& p : s.inputCatalogPaths) inputs.push_back({"INPUT_CATALOG", p});
  if (!assocListPath.empty()) inputs.push_back({"ASSOC_NAME", assocListPath});
  return inputs;
}

}  // namespace octarc
