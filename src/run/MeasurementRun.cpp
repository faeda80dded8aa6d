#include "octarc/run/MeasurementRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/SegmentationReader.h"
#include "octarc/io/FitsImage.h"
#include "octarc/run/Levels.h"

namespace octarc {

namespace {

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

// Measures one image extension (`e` of `count`).
MeasuredExtension measureExtension(const RunSettings& s, const ColumnPlan& columns,
                                   const std::optional<sexcompat::AssocSettings>& assoc,
                                   const InputCatalogs& catalogs, const std::string& path, int e,
                                   int count, std::chrono::steady_clock::time_point start,
                                   MeasurementRunResult& result, const RunLog& log) {
  const std::size_t levelCount = s.segmentationPaths.size();
  std::vector<CatalogRunValues> catalogValues;
  for (std::size_t k = 0; k < catalogs.parts.size(); ++k) {
    if (int(catalogs.parts[k].size()) != count) {
      throw IoError(s.inputCatalogPaths[k] + ": catalog has " +
                    std::to_string(catalogs.parts[k].size()) + " object tables but the image has " +
                    std::to_string(count) + " extensions");
    }
    catalogValues.push_back(catalogs.values[k][std::size_t(e)]);
  }
  if (log) log("> Reading " + path);
  const PreparedImage image =
      prepareImage(path, settingsForExtension(s, e, count),
                   catalogValues.empty() ? CatalogRunValues{} : catalogValues[0], false);
  MeasuredExtension out;
  out.header = image.hdu.header;
  if (log) {
    for (const std::string& w : image.warnings) log("WARNING: " + w);
  }

  std::vector<std::string> segPaths;
  for (const std::string& p : s.segmentationPaths) {
    segPaths.push_back(extensionPath(p, e, count, "segmentation image"));
  }
  const std::vector<Segment> segments =
      readSegmentation(segPaths, image.hdu.pixels.width(), image.hdu.pixels.height());
  MeasureContext context = image.context(s);
  context.levels = levelThresholds(s, image.sigmaAdu, catalogValues, levelCount);
  if (log) {
    std::ostringstream line;
    line << "> Measuring " << segments.size() << " objects at " << levelCount << " level(s)";
    log(line.str());
  }
  Table full(columns.plan.columns());
  measureSegments(columns.plan, segments, context, full, resolveThreads(s.threads));

  // Every label must have its catalog row and every row its label: for each level, the
  // measured row of each catalog row.
  for (std::size_t k = 0; k < catalogs.parts.size(); ++k) {
    out.catalogRows.push_back(joinByNumber(segments, int(k) + 1, catalogs.parts[k][std::size_t(e)],
                                           s.inputCatalogPaths[k], segPaths[k]));
  }

  out.levelCount = std::int64_t(context.levels.size());
  RunFacts facts;
  facts.imagePath = s.imagePaths[0];
  facts.extension = e;
  facts.extensionCount = count;
  facts.detectedCount = std::int64_t(segments.size());
  facts.parameterCount = int(columns.outputColumns.size());
  auto elapsedSec = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (result.append) {
    // ASSOC fills its columns for every row: the rows are those of the input catalogs.
    if (assoc) applyAssoc(*assoc, columns.assocVectorSize, image, full, s.quiet, true);
    // The rows stay where they were measured; each catalog takes its own, in its row order.
    facts.finalCount = full.rows();
    facts.elapsedSec = elapsedSec();
    out.summary = runSummary(s, image, context.levels, facts);
    out.cards = appendedRunCards(out.summary, image, context.levels);
    out.table = std::move(full);
  } else {
    if (assoc) applyAssoc(*assoc, columns.assocVectorSize, image, full, s.quiet);
    out.table = outputTable(columns, std::move(full));
    facts.finalCount = out.table.rows();
    facts.elapsedSec = elapsedSec();
    const RunSummary summary = runSummary(s, image, context.levels, facts);
    out.summary = summary;
    if (e == 0) result.fits10Cards = sexFits10Cards(summary);
    out.cards = runHeaderCards(summary, image, context.levels);
    out.catalogRows.clear();
  }
  return out;
}

}  // namespace

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

InputCatalogs readInputCatalogs(const RunSettings& s) {
  InputCatalogs catalogs;
  for (const std::string& path : s.inputCatalogPaths) {
    catalogs.parts.push_back(readInputCatalog(path));
    catalogs.values.emplace_back();
    for (const InputCatalogPart& part : catalogs.parts.back()) {
      catalogs.values.back().push_back(catalogRunValues(part, path));
    }
  }
  return catalogs;
}

std::vector<CatalogPart> MeasurementRunResult::parts() const {
  std::vector<CatalogPart> out;
  for (const MeasuredExtension& x : extensions)
    out.push_back({x.header, x.cards, &x.table, nullptr});
  return out;
}

std::vector<AppendedColumns> MeasurementRunResult::appendedColumns(
    std::size_t level, const ColumnPlan& columns, const InputCatalogs& catalogs) const {
  if (!append) throw Error("appendedColumns: the run did not append to its input catalogs");
  std::vector<AppendedColumns> out;
  for (std::size_t e = 0; e < extensions.size(); ++e) {
    const MeasuredExtension& x = extensions[e];
    AppendedColumns a;
    a.table = &x.table;
    const std::vector<std::string>& existing = catalogs.parts[level][e].columnNames;
    for (const ColumnSpec& c : columns.outputColumns) {
      if (std::find(existing.begin(), existing.end(), c.name) == existing.end()) {
        a.columns.push_back(x.table.findColumn(c.name));
      }
    }
    if (a.columns.empty()) a.table = nullptr;
    a.rows = &x.catalogRows[level];
    a.cards = x.cards;
    out.push_back(std::move(a));
  }
  return out;
}

MeasurementRunResult runMeasurement(const RunSettings& s, const ColumnPlan& columns,
                                    const std::optional<sexcompat::AssocSettings>& assoc,
                                    const InputCatalogs& catalogs, const RunLog& log) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> extensions = listImageHdus(s.imagePaths[0]);
  const int count = int(extensions.size());
  MeasurementRunResult result;
  result.append = !s.inputCatalogPaths.empty() && s.appendColumns;
  result.extensions.reserve(std::size_t(count));
  for (int e = 0; e < count; ++e) {
    result.extensions.push_back(measureExtension(
        s, columns, assoc, catalogs, extensions[std::size_t(e)], e, count, start, result, log));
  }
  return result;
}

}  // namespace octarc
