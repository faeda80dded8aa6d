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

#include "octarc/catalog/AppendedCatalog.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/SegmentationReader.h"
#include "octarc/io/FitsImage.h"
#include "octarc/pipeline/CatalogAssembly.h"
#include "octarc/pipeline/CommandLine.h"
#include "octarc/pipeline/Pipeline.h"
#include "octarc/pipeline/PreparedImage.h"
#include "octarc/pipeline/RunSettings.h"

namespace octarc {

namespace {

// Thresholds of each level: from the input catalogs (SEXTHLD/SEXATHLD) when given, otherwise
// DETECT_LEVELS (one per segmentation image), otherwise DETECT_THRESH/ANALYSIS_THRESH for a
// single level.
std::vector<ThresholdLevel> levelThresholds(const RunSettings& s, double sigmaAdu,
                                            const std::vector<CatalogRunValues>& catalogs,
                                            std::size_t levelCount) {
  // With catalogs, their SEXTHLD is the threshold of each level; DETECT_LEVELS (or, for a single
  // level, DETECT_THRESH) stands in for a catalog without one.
  if (s.detectLevels.empty() && levelCount > 1) {
    for (std::size_t k = 0; k < catalogs.size(); ++k) {
      if (!catalogs[k].thresholdAdu) {
        throw IoError(s.inputCatalogPaths[k] +
                      ": no SEXTHLD (the detection threshold of its run) in the LDAC_IMHEAD of "
                      "its objects table; give the thresholds of the levels with DETECT_LEVELS");
      }
    }
  }
  std::vector<ThresholdLevel> levels(levelCount);
  const bool detRel = s.detectThresholdType == ThresholdType::Relative;
  const bool anaRel = s.analysisThresholdType == ThresholdType::Relative;
  for (std::size_t k = 0; k < levelCount; ++k) {
    ThresholdLevel& l = levels[k];
    l.level = int(k) + 1;
    if (k < catalogs.size() && catalogs[k].thresholdAdu) {
      l.thresholdAdu = *catalogs[k].thresholdAdu;
      l.analysisThresholdAdu = catalogs[k].analysisThresholdAdu.value_or(l.thresholdAdu);
    } else if (!s.detectLevels.empty()) {
      if (s.detectLevels.size() != levelCount) {
        throw ConfigError("DETECT_LEVELS lists " + std::to_string(s.detectLevels.size()) +
                          " thresholds but SEGMENTATION_NAME has " + std::to_string(levelCount) +
                          " images");
      }
      l.thresholdAdu = thresholdToAdu(s.detectLevels[k], detRel, sigmaAdu);
      l.analysisThresholdAdu = l.thresholdAdu;
    } else if (levelCount == 1) {
      l.thresholdAdu = thresholdToAdu(s.detectThreshold, detRel, sigmaAdu);
      l.analysisThresholdAdu = thresholdToAdu(s.analysisThreshold, anaRel, sigmaAdu);
    } else {
      throw ConfigError(
          "several SEGMENTATION_NAME images: give their thresholds with DETECT_LEVELS or their "
          "catalogs with INPUT_CATALOG");
    }
    l.thresholdSigma = sigmaAdu > 0 ? l.thresholdAdu / sigmaAdu : std::nan("");
  }
  return levels;
}

// Checks that labels and catalog rows match one to one (per level) and returns, for each
// catalog row, the index of its segment.
std::vector<std::int64_t> joinByNumber(const std::vector<Segment>& segments, int level,
                                       const InputCatalogPart& catalog,
                                       const std::string& catalogPath, const std::string& segPath) {
  std::map<std::int64_t, std::int64_t> byNumber;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].level == level) byNumber[segments[i].number] = std::int64_t(i);
  }
  std::vector<std::int64_t> order;
  std::set<std::int64_t> seen;
  for (std::int64_t number : catalog.numbers) {
    auto it = byNumber.find(number);
    if (it == byNumber.end()) {
      throw IoError(catalogPath + ": catalog row NUMBER " + std::to_string(number) +
                    " has no label in " + segPath);
    }
    if (!seen.insert(number).second) {
      throw IoError(catalogPath + ": NUMBER " + std::to_string(number) + " appears twice");
    }
    order.push_back(it->second);
  }
  for (const auto& [number, index] : byNumber) {
    if (!seen.count(number)) {
      throw IoError(segPath + ": label " + std::to_string(number) + " has no row in " +
                    catalogPath);
    }
  }
  return order;
}

void printUsage() {
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
  std::optional<LoadedRun> run = loadRun(args, "measure", printUsage);
  if (!run) return 0;
  const RunSettings& s = run->settings;
  requireSingleImage(s, "measure");
  if (s.segmentationPaths.empty()) {
    throw ConfigError("SEGMENTATION_NAME is required: the SExtractor segmentation check-image(s)");
  }
  const std::string& imagePath = s.imagePaths[0];
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

  // Every catalog and its run values are checked before any image is read.
  std::vector<std::vector<InputCatalogPart>> catalogs;
  std::vector<std::vector<CatalogRunValues>> runValues;
  for (const std::string& path : s.inputCatalogPaths) {
    catalogs.push_back(readInputCatalog(path));
    runValues.emplace_back();
    for (const InputCatalogPart& part : catalogs.back()) {
      runValues.back().push_back(catalogRunValues(part, path));
    }
  }

  const std::vector<std::string> extensions = listImageHdus(imagePath);
  const int extCount = int(extensions.size());
  std::vector<CatalogPart> parts;
  std::vector<Table> tables;  // per extension (new-catalog mode)
  // Append mode, per extension: the measured rows of every level, the rows each level's catalog
  // takes from them, and the run's provenance cards.
  std::vector<Table> measured(appendMode ? std::size_t(extCount) : 0);
  std::vector<std::vector<std::vector<std::int64_t>>> catalogRows(measured.size());
  std::vector<std::vector<std::string>> provenance(measured.size());
  std::vector<std::vector<AppendedColumns>> appended(levelCount);  // [level][extension]
  std::vector<std::vector<std::string>> cards;
  std::vector<std::string> fits10Cards;
  tables.reserve(std::size_t(extCount));
  cards.reserve(std::size_t(extCount));
  std::vector<FitsHeader> headers;  // per extension, for LDAC_IMHEAD

  for (int e = 0; e < extCount; ++e) {
    std::vector<CatalogRunValues> catalogValues;
    for (std::size_t k = 0; k < catalogs.size(); ++k) {
      if (int(catalogs[k].size()) != extCount) {
        throw IoError(s.inputCatalogPaths[k] + ": catalog has " +
                      std::to_string(catalogs[k].size()) + " object tables but the image has " +
                      std::to_string(extCount) + " extensions");
      }
      catalogValues.push_back(runValues[k][std::size_t(e)]);
    }
    if (!s.quiet) std::cerr << "> Reading " << extensions[std::size_t(e)] << "\n";
    const PreparedImage image =
        prepareImage(extensions[std::size_t(e)], settingsForExtension(s, e, extCount),
                     catalogValues.empty() ? CatalogRunValues{} : catalogValues[0], false);
    headers.push_back(image.hdu.header);
    if (!s.quiet) {
      for (const std::string& w : image.warnings) std::cerr << "WARNING: " << w << "\n";
    }

    std::vector<std::string> segPaths;
    for (const std::string& p : s.segmentationPaths) {
      segPaths.push_back(extensionPath(p, e, extCount, "segmentation image"));
    }
    const std::vector<Segment> segments =
        readSegmentation(segPaths, image.hdu.pixels.width(), image.hdu.pixels.height());
    MeasureContext context = image.context(s);
    context.levels = levelThresholds(s, image.sigmaAdu, catalogValues, levelCount);

    if (!s.quiet) {
      std::cerr << "> Measuring " << segments.size() << " objects at " << levelCount
                << " level(s)\n";
    }
    Table full(columns.plan.columns());
    measureSegments(columns.plan, segments, context, full, resolveThreads(s.threads));

    // Every label must have its catalog row and every row its label: for each level, the
    // measured row of each catalog row.
    std::vector<std::vector<std::int64_t>> rowOrder;
    for (std::size_t k = 0; k < catalogs.size(); ++k) {
      rowOrder.push_back(joinByNumber(segments, int(k) + 1, catalogs[k][std::size_t(e)],
                                      s.inputCatalogPaths[k], segPaths[k]));
    }

    RunFacts facts;
    facts.imagePath = imagePath;
    facts.extension = e;
    facts.extensionCount = extCount;
    facts.detectedCount = std::int64_t(segments.size());
    facts.parameterCount = int(columns.outputColumns.size());
    if (appendMode) {
      // ASSOC fills its columns for every row: the rows are those of the input catalogs.
      if (assocSettings) {
        applyAssoc(*assocSettings, columns.assocVectorSize, image, full, s.quiet, true);
      }
      // The rows stay where they were measured; each catalog takes its own, in its row order.
      facts.finalCount = full.rows();
      facts.elapsedSec =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      provenance[std::size_t(e)] =
          appendedRunCards(runSummary(s, image, context.levels, facts), image, context.levels);
      measured[std::size_t(e)] = std::move(full);
      catalogRows[std::size_t(e)] = std::move(rowOrder);
    } else {
      if (assocSettings) {
        applyAssoc(*assocSettings, columns.assocVectorSize, image, full, s.quiet);
      }
      tables.push_back(outputTable(columns, std::move(full)));
      facts.finalCount = tables.back().rows();
      facts.elapsedSec =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const RunSummary summary = runSummary(s, image, context.levels, facts);
      if (e == 0) fits10Cards = sexFits10Cards(summary);
      cards.push_back(runHeaderCards(summary, image, context.levels));
    }
  }

  if (appendMode) {
    for (std::size_t k = 0; k < levelCount; ++k) {
      for (std::size_t e = 0; e < measured.size(); ++e) {
        AppendedColumns a;
        a.table = &measured[e];
        // Columns the SExtractor catalog already has are kept as they are, not appended again.
        const std::vector<std::string>& existing = catalogs[k][e].columnNames;
        for (const ColumnSpec& c : columns.outputColumns) {
          if (std::find(existing.begin(), existing.end(), c.name) == existing.end()) {
            a.columns.push_back(measured[e].findColumn(c.name));
          }
        }
        if (a.columns.empty()) a.table = nullptr;
        a.rows = &catalogRows[e][k];
        a.cards = provenance[e];
        appended[k].push_back(std::move(a));
      }
      outputs.write(k, [&](const std::string& path) {
        writeAppendedCatalog(s.inputCatalogPaths[k], catalogs[k], path, appended[k]);
      });
    }
  } else if (catalogType != CatalogType::None) {
    for (int e = 0; e < extCount; ++e) {
      parts.push_back(
          {headers[std::size_t(e)], cards[std::size_t(e)], &tables[std::size_t(e)], nullptr});
    }
    outputs.write(
        0, [&](const std::string& path) { writeCatalog(path, catalogType, parts, fits10Cards); });
  }
  // Every catalog is complete: they appear together.
  outputs.commit();
  if (!s.quiet) {
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      std::cerr << "> Wrote " << outputs[i].finalPath() << "\n";
    }
  }
  return 0;
}

}  // namespace octarc
