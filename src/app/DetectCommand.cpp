// `octarc detect`: every threshold in one pass, no deblending, every object measured.
//
//   image --> background/noise --> (filter) --> multi-threshold detection (one pass)
//         --> measurements (per object, per level) --> catalog [+ check-images]

#include <algorithm>
#include <chrono>
#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Progress.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/MeasureJob.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunKeys.h"
#include "octarc/run/RunSettings.h"

namespace octarc {

namespace {

// clang-format off
void printDetectUsage() {
  std::cout <<
      "Usage: octarc detect IMAGE [-c config.sex] [-KEY value ...]\n"
      "       octarc detect DETECT_IMAGE,MEASURE_IMAGE [-c config.sex] [-KEY value ...]\n"
      "\n"
      "Detects objects at many thresholds in one pass over IMAGE (pure thresholding: pixels\n"
      "strictly above the level, 8-connected, at least DETECT_MINAREA of them, no deblending,\n"
      "no cleaning), measures every object at every level and writes one catalog with a row per\n"
      "object per level (THRESH_LEVEL, NUMBER within the level, PARENT_NUMBER one level down).\n"
      "\n"
      "Levels: DETECT_NLEVELS thresholds spaced logarithmically from DETECT_THRESH to\n"
      "DETECT_THRESH_MAX (THRESH_TYPE RELATIVE: in units of the background sigma; ABSOLUTE: ADU),\n"
      "or the explicit list DETECT_LEVELS. DETECT_NLEVELS 1 is a plain SExtractor run.\n"
      "CHECKIMAGE_TYPE SEGMENTATION writes one int32 HDU per level.\n"
      "\n"
      "Weight maps: WEIGHT_TYPE MAP_WEIGHT, MAP_RMS or MAP_VAR with WEIGHT_IMAGE (and\n"
      "WEIGHT_THRESH, RESCALE_WEIGHTS) as in SExtractor: RELATIVE levels become t * sqrt(var)\n"
      "per pixel, bad weight pixels never join an object, FLUXERR_ISO uses the variances.\n"
      "\n"
      "Dual-image mode (DETECT_IMAGE,MEASURE_IMAGE, or the two names apart), as SExtractor's:\n"
      "footprints, positions and shapes from the first image, photometry and the octopole\n"
      "moments from the second, each with its own background and noise; both on one pixel grid.\n"
      "BACK_TYPE, BACK_VALUE, WEIGHT_TYPE, WEIGHT_IMAGE and WEIGHT_THRESH take a second value\n"
      "for the measurement image (e.g. -WEIGHT_IMAGE det.weight.fits,meas.weight.fits).\n"
      "A constant image gives no object: as SExtractor, the noise sigma is set to 1 with a\n"
      "warning. An image without any finite pixel is an error.\n"
      "\n"
      "Options:\n"
      "  -c FILE      configuration file (SExtractor .sex syntax; see share/octarc/octarc.sex)\n"
      "  -KEY value   override a configuration key (e.g. -DETECT_NLEVELS 15)\n"
      "  -d, -dd      print the default configuration (-dd: every key)\n"
      "  -dp          list every catalog column with its description and unit\n"
      "  -h           this help;  -v  version\n";
}
// clang-format on

}  // namespace

int runDetect(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<LoadedRun> run =
      loadRun(args, {"detect", printDetectUsage, printMeasuredColumns}, octarcKeys());
  if (!run) return 0;
  requireImages(run->settings, "detect", true);
  const RunSettings& s = run->settings;
  if (s.catalogNames.size() != 1) throw ConfigError("CATALOG_NAME must be one file name");
  const std::vector<std::string>& supported = detectCheckImageTypes();
  for (const std::string& t : s.checkImageTypes) {
    if (std::find(supported.begin(), supported.end(), t) == supported.end()) {
      throw ConfigError("CHECKIMAGE_TYPE " + t +
                        " is not supported (SEGMENTATION, BACKGROUND, BACKGROUND_RMS, "
                        "-BACKGROUND, FILTERED, OBJECTS)");
    }
  }
  // The level list is checked before any image is read.
  const int levelCount = int(detectionLevels(s, 1.0).size());
  // A maximum without a number of levels is probably meant for a multi-threshold run.
  if (levelCount == 1 && run->config.isExplicit("DETECT_THRESH_MAX") &&
      !run->config.isExplicit("DETECT_NLEVELS") && !s.quiet) {
    std::cerr << "WARNING: DETECT_THRESH_MAX is set but DETECT_NLEVELS is 1: one level, at "
                 "DETECT_THRESH (set DETECT_NLEVELS for a multi-threshold run)\n";
  }
  if (s.minAreaPix < 1) {
    throw ConfigError("DETECT_MINAREA: must be at least 1, got " + std::to_string(s.minAreaPix));
  }
  const CatalogType catalogType = parseCatalogType(s.catalogType);
  const ColumnPlan columns = planColumns(s, s.quiet, levelCount);
  std::optional<sexcompat::AssocSettings> assocSettings;
  if (columns.assoc) assocSettings = sexcompat::AssocSettings::fromConfig(run->config);

  // The outputs, checked before any pixel is read: the catalog first (the run's main output),
  // then the check images; they are renamed into place together at the end.
  OutputFiles outputs;
  if (catalogType != CatalogType::None) outputs.add(s.catalogNames[0]);
  const std::size_t firstCheck = outputs.size();
  for (const std::string& name : s.checkImageNames) outputs.add(name);
  const std::vector<NamedInput> inputs =
      runInputs(s, assocSettings ? assocSettings->listPath : std::string());
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const std::string key = i < firstCheck ? "CATALOG_NAME" : "CHECKIMAGE_NAME";
    for (const NamedInput& in : inputs) {
      refuseOutputOverInput(outputs[i].finalPath(), key, in.path, in.key);
    }
  }
  const int xmlOutput = addXmlOutput(s, outputs, inputs);

  const RunLog log =
      s.quiet ? RunLog() : [](const std::string& line) { std::cerr << line << "\n"; };
  DetectionRunResult result = runDetection(s, columns, assocSettings, log);

  // VERBOSE_TYPE FULL reports where the time goes.
  StageClock clock(s.verboseFull, log);
  std::vector<CatalogPart> parts = result.parts();
  clock.lap("assembling the catalog");
  if (catalogType != CatalogType::None) {
    outputs.write(0, [&](const std::string& path) {
      writeCatalog(path, catalogType, parts, result.fits10Cards);
    });
  }
  clock.lap("writing the catalog");
  if (!s.quiet && catalogType != CatalogType::None) {
    std::cerr << "> Wrote " << s.catalogNames[0] << " in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
  }
  XmlRunFacts xml;
  for (const DetectedExtension& x : result.extensions) {
    xml.extensions.push_back(x.summary);
    xml.levelCounts.push_back(std::int64_t(x.levels.size()));
  }
  // Check images last. The catalog is written: its rows make room for their buffer.
  parts.clear();
  std::vector<DetectedExtension>().swap(result.extensions);
  writeCheckImages(s, result, outputs, firstCheck, log);
  if (xmlOutput >= 0) {
    xml.commandLine = commandLineText("detect", args);
    xml.warnings = run->warnings;
    xml.durationSec =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    outputs.write(std::size_t(xmlOutput), [&](const std::string& path) {
      writeTextFile(path, runXmlText(s, run->config, octarcKeys(), columns.outputColumns, xml));
    });
  }
  // Every output is complete: they appear together.
  outputs.commit();
  return 0;
}

}  // namespace octarc
