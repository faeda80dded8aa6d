// `octarc measure`: the measurement module on a SExtractor run's segmentation check-images.
//
//   image --> background/noise --> segmentation images (one per threshold, nested)
//         --> measurements --> catalog (new, or the SExtractor catalog(s) with columns appended)

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <set>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/catalog/AppendedCatalog.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/SegmentationReader.h"
#include "octarc/io/FitsImage.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/Levels.h"
#include "octarc/run/MeasurementRun.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunKeys.h"
#include "octarc/run/RunSettings.h"

namespace octarc {

namespace {

void printMeasureUsage() {
  std::cout
      << "Usage: octarc measure IMAGE [-c config.sex] [-KEY value ...]\n"
         "\n"
         "Measures every object of SExtractor SEGMENTATION check-images (one per threshold, "
         "lowest\n"
         "first: -SEGMENTATION_NAME seg1.fits[,seg2.fits,...]) on IMAGE and writes a catalog with\n"
         "SExtractor's isophotal columns and octarc's octopole (arcness) columns. With\n"
         "-INPUT_CATALOG cat1.ldac[,...] the output is each SExtractor catalog with the requested\n"
         "octarc columns appended, joined by NUMBER (one CATALOG_NAME per input catalog).\n"
         "\n"
         "Options:\n"
         "  -c FILE      configuration file (SExtractor .sex syntax)\n"
         "  -KEY value   override a configuration key (e.g. -CATALOG_NAME out.cat)\n"
         "  -d, -dd      print the default configuration (-dd: every key)\n"
         "  -dp          list every catalog column with its description and unit\n"
         "  -h           this help;  -v  version\n";
}

}  // namespace

int runMeasure(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<LoadedRun> run =
      loadRun(args, {"measure", printMeasureUsage, printMeasuredColumns}, octarcKeys());
  if (!run) return 0;
  requireImages(run->settings, "measure", false);
  const RunSettings& s = run->settings;
  if (s.segmentationPaths.empty()) {
    throw ConfigError("SEGMENTATION_NAME is required: the SExtractor segmentation check-image(s)");
  }
  const std::size_t levelCount = s.segmentationPaths.size();
  const bool withCatalogs = !s.inputCatalogPaths.empty();
  const bool appendMode = withCatalogs && s.appendColumns;
  if (withCatalogs && s.inputCatalogPaths.size() != levelCount) {
    throw ConfigError("INPUT_CATALOG lists " + std::to_string(s.inputCatalogPaths.size()) +
                      " catalogs but SEGMENTATION_NAME has " + std::to_string(levelCount) +
                      " images: give one catalog per segmentation image");
  }
  if (appendMode && s.catalogNames.size() != levelCount) {
    throw ConfigError("CATALOG_NAME must list one output per INPUT_CATALOG (" +
                      std::to_string(levelCount) + ")");
  }
  if (!appendMode && s.catalogNames.size() != 1) {
    throw ConfigError("CATALOG_NAME must be one file name");
  }
  // Appending keeps each input catalog's own format; CATALOG_TYPE is for new catalogs.
  const CatalogType catalogType = parseCatalogType(s.catalogType);
  if (appendMode && run->config.isExplicit("CATALOG_TYPE") && !s.quiet) {
    std::cerr << "WARNING: CATALOG_TYPE " << s.catalogType
              << " is not used with APPEND_COLUMNS Y: each output keeps the format of its "
                 "INPUT_CATALOG\n";
  }

  // Appended catalogs hold one level each; a new catalog holds every level.
  const ColumnPlan columns = planColumns(s, s.quiet, appendMode ? 1 : int(levelCount));
  std::optional<sexcompat::AssocSettings> assocSettings;
  if (columns.assoc) assocSettings = sexcompat::AssocSettings::fromConfig(run->config);
  if (appendMode && assocSettings && !s.quiet &&
      assocSettings->selection != sexcompat::AssocSelection::All) {
    std::cerr << "WARNING: ASSOCSELEC_TYPE " << run->config.getString("ASSOCSELEC_TYPE")
              << " does not remove rows with APPEND_COLUMNS Y: every row of the input catalogs is "
                 "kept, with its VECTOR_ASSOC/NUMBER_ASSOC (APPEND_COLUMNS N selects rows)\n";
  }

  // The outputs, checked before anything is read; renamed into place together at the end.
  OutputFiles outputs;
  if (appendMode || catalogType != CatalogType::None) {
    for (const std::string& name : s.catalogNames) outputs.add(name);
  }
  const std::vector<NamedInput> inputs =
      runInputs(s, assocSettings ? assocSettings->listPath : std::string());
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (const NamedInput& in : inputs) {
      // Only with REPLACE_INPUT_CATALOG Y may an appended catalog take its own input's name.
      if (appendMode && s.replaceInputCatalog && in.key == "INPUT_CATALOG" &&
          in.path == s.inputCatalogPaths[i]) {
        continue;
      }
      refuseOutputOverInput(outputs[i].finalPath(), "CATALOG_NAME", in.path,
                            in.key == "INPUT_CATALOG" && appendMode
                                ? "INPUT_CATALOG (REPLACE_INPUT_CATALOG Y replaces it)"
                                : in.key);
    }
  }
  const int xmlOutput = addXmlOutput(s, outputs, inputs);

  // Every catalog and its run values are checked before any image is read.
  const InputCatalogs catalogs = readInputCatalogs(s);
  const RunLog log =
      s.quiet ? RunLog() : [](const std::string& line) { std::cerr << line << "\n"; };
  const MeasurementRunResult result = runMeasurement(s, columns, assocSettings, catalogs, log);
  if (appendMode) {
    for (std::size_t k = 0; k < levelCount; ++k) {
      const std::vector<AppendedColumns> appended = result.appendedColumns(k, columns, catalogs);
      outputs.write(k, [&](const std::string& path) {
        writeAppendedCatalog(s.inputCatalogPaths[k], catalogs.parts[k], path, appended);
      });
    }
  } else if (catalogType != CatalogType::None) {
    outputs.write(0, [&](const std::string& path) {
      writeCatalog(path, catalogType, result.parts(), result.fits10Cards);
    });
  }
  if (xmlOutput >= 0) {
    XmlRunFacts xml;
    for (const MeasuredExtension& x : result.extensions) {
      xml.extensions.push_back(x.summary);
      xml.levelCounts.push_back(x.levelCount);
    }
    xml.commandLine = commandLineText("measure", args);
    xml.warnings = run->warnings;
    xml.durationSec =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    outputs.write(std::size_t(xmlOutput), [&](const std::string& path) {
      writeTextFile(path, runXmlText(s, run->config, octarcKeys(), columns.outputColumns, xml));
    });
  }
  // Every output is complete: they appear together.
  outputs.commit();
  if (!s.quiet) {
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      std::cerr << "> Wrote " << outputs[i].finalPath() << "\n";
    }
  }
  return 0;
}

}  // namespace octarc
