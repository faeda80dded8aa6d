#include "octarc/run/RunSettings.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

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

BackgroundType backgroundType(const std::string& keyword) {
  const std::string type = uppercase(keyword);
  return type == "MANUAL"   ? BackgroundType::Manual
         : type == "GLOBAL" ? BackgroundType::Global
                            : BackgroundType::Auto;
}

// WEIGHT_TYPE value `index` (ConfigError for the unsupported BACKGROUND).
WeightType weightType(const sexcompat::Config& config, std::size_t index, std::string& name) {
  name = uppercase(config.getString("WEIGHT_TYPE", index));
  if (name == "BACKGROUND") {
    throw ConfigError(
        "WEIGHT_TYPE BACKGROUND is not supported; give a map with MAP_WEIGHT, MAP_RMS or MAP_VAR");
  }
  return name == "MAP_WEIGHT" ? WeightType::MapWeight
         : name == "MAP_RMS"  ? WeightType::MapRms
         : name == "MAP_VAR"  ? WeightType::MapVariance
                              : WeightType::None;
}

std::size_t secondIndex(const sexcompat::Config& config, const char* key) {
  return config.count(key) > 1 ? 1 : 0;
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

  s.backgroundType = backgroundType(config.getString("BACK_TYPE", 0));
  s.backgroundValueAdu = config.getDouble("BACK_VALUE", 0);
  s.measurement.backgroundType = backgroundType(secondOrFirst(config, "BACK_TYPE"));
  s.measurement.backgroundValueAdu =
      config.getDouble("BACK_VALUE", secondIndex(config, "BACK_VALUE"));
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
  std::string typeName, measurementTypeName;
  s.weightType = weightType(config, 0, typeName);
  s.measurement.weightType =
      weightType(config, secondIndex(config, "WEIGHT_TYPE"), measurementTypeName);
  if (!weightMapsElsewhere) {
    const bool anyWeights =
        s.weightType != WeightType::None || s.measurement.weightType != WeightType::None;
    if (anyWeights && !config.isExplicit("WEIGHT_IMAGE")) {
      throw ConfigError("WEIGHT_IMAGE: WEIGHT_TYPE " +
                        (s.weightType != WeightType::None ? typeName : measurementTypeName) +
                        " needs a weight map file");
    }
    if (s.weightType != WeightType::None) s.weightImagePath = config.getString("WEIGHT_IMAGE", 0);
    if (s.measurement.weightType != WeightType::None) {
      s.measurement.weightImagePath =
          config.getString("WEIGHT_IMAGE", secondIndex(config, "WEIGHT_IMAGE"));
    }
  }
  if (config.isExplicit("WEIGHT_THRESH")) {
    s.weightThreshold = config.getDouble("WEIGHT_THRESH", 0);
    s.measurement.weightThreshold =
        config.getDouble("WEIGHT_THRESH", secondIndex(config, "WEIGHT_THRESH"));
  }
  s.rescaleWeights = config.getBool("RESCALE_WEIGHTS");
  s.weightGain = config.getBool("WEIGHT_GAIN");
  if ((s.weightType != WeightType::None || s.measurement.weightType != WeightType::None) &&
      !s.weightGain) {
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
  s.writeXml = config.getBool("WRITE_XML");
  s.xmlName = config.getString("XML_NAME");
  s.xslUrl = config.getString("XSL_URL");
  s.threads = config.getInt("NTHREADS");
  return s;
}

void setImagePaths(RunSettings& s, const std::vector<std::string>& arguments) {
  // SExtractor's DETECT,MEASURE: a comma in a name that is no file separates two images.
  std::vector<std::string> paths;
  for (const std::string& argument : arguments) {
    std::error_code ec;
    if (argument.find(',') == std::string::npos || std::filesystem::exists(argument, ec)) {
      paths.push_back(argument);
      continue;
    }
    std::size_t from = 0;
    for (std::size_t comma; (comma = argument.find(',', from)) != std::string::npos;
         from = comma + 1) {
      paths.push_back(argument.substr(from, comma - from));
    }
    paths.push_back(argument.substr(from));
    if (std::any_of(paths.begin(), paths.end(), [](const std::string& p) { return p.empty(); })) {
      throw ConfigError("command line: " + quoteForMessage(argument) +
                        " is neither a file nor DETECT_IMAGE,MEASURE_IMAGE");
    }
  }
  if (paths.empty() || paths.size() > 2) {
    throw ConfigError(
        "give one image, or a detection and a measurement image (DETECT,MEASURE); "
        "got " +
        std::to_string(paths.size()));
  }
  s.imagePaths = paths;
  if (s.dualImage() && (!s.backgroundMapPath.empty() || !s.backgroundRmsMapPath.empty())) {
    throw ConfigError(
        std::string(s.backgroundMapPath.empty() ? "BACKGROUND_RMS_NAME" : "BACKGROUND_NAME") +
        ": background maps are for one image, not for a dual-image run");
  }
}

RunSettings measurementImageSettings(const RunSettings& settings) {
  RunSettings out = settings;
  out.backgroundType = settings.measurement.backgroundType;
  out.backgroundValueAdu = settings.measurement.backgroundValueAdu;
  out.weightType = settings.measurement.weightType;
  out.weightImagePath = settings.measurement.weightImagePath;
  out.weightThreshold = settings.measurement.weightThreshold;
  out.filter = false;
  return out;
}

std::vector<NamedInput> runInputs(const RunSettings& s, const std::string& assocListPath) {
  std::vector<NamedInput> inputs;
  for (const std::string& p : s.imagePaths) inputs.push_back({"image", p});
  if (!s.configPath.empty()) inputs.push_back({"configuration file", s.configPath});
  inputs.push_back({"PARAMETERS_NAME", s.parametersPath});
  if (s.filter) inputs.push_back({"FILTER_NAME", s.filterPath});
  if (!s.weightImagePath.empty()) inputs.push_back({"WEIGHT_IMAGE", s.weightImagePath});
  if (s.dualImage() && !s.measurement.weightImagePath.empty()) {
    inputs.push_back({"WEIGHT_IMAGE", s.measurement.weightImagePath});
  }
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
