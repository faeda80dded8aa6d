// `octarc detect`: every threshold in one pass, no deblending, every object measured.
//
//   image --> background/noise --> (filter) --> multi-threshold detection (one pass)
//         --> measurements (per object, per level) --> catalog [+ check-images]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numeric>
#include <set>

#include "octarc/catalog/Catalog.h"
#include "octarc/core/Error.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/io/FitsImage.h"
#include "octarc/pipeline/CatalogAssembly.h"
#include "octarc/pipeline/CommandLine.h"
#include "octarc/pipeline/Pipeline.h"
#include "octarc/pipeline/PreparedImage.h"
#include "octarc/pipeline/RunSettings.h"

namespace octarc {

namespace {

const std::set<std::string> kCheckImageTypes = {"SEGMENTATION", "BACKGROUND", "BACKGROUND_RMS",
                                                "-BACKGROUND",  "FILTERED",   "OBJECTS"};

// Objects are measured in batches of this many, so that pixel lists never pile up.
constexpr std::size_t kMeasureBatch = 16384;

void printUsage() {
  std::cout <<
      "Usage: octarc detect IMAGE [-c config.sex] [-KEY value ...]\n"
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
      "Options:\n"
      "  -c FILE      configuration file (SExtractor .sex syntax; see params/octarc.sex)\n"
      "  -KEY value   override a configuration key (e.g. -DETECT_NLEVELS 15)\n"
      "  -d, -dd      print the default configuration (-dd: every key)\n"
      "  -dp          list every catalog column with its description and unit\n"
      "  -h           this help;  -v  version\n";
}

// The detection levels in ADU, lowest first.
std::vector<ThresholdLevel> detectionLevels(const RunSettings& s, double sigmaAdu) {
  const bool relative = s.detectThresholdType == ThresholdType::Relative;
  std::vector<double> values = s.detectLevels;
  if (values.empty()) {
    const int n = s.detectLevelCount;
    if (n < 1) throw ConfigError("DETECT_NLEVELS must be at least 1");
    if (n == 1) {
      values.push_back(s.detectThreshold);
    } else {
      if (!(s.detectThresholdMax > s.detectThreshold) || s.detectThreshold <= 0) {
        throw ConfigError("DETECT_THRESH_MAX (" + std::to_string(s.detectThresholdMax) +
                          ") must be above DETECT_THRESH (" + std::to_string(s.detectThreshold) +
                          "), both positive, for several levels");
      }
      const double ratio = s.detectThresholdMax / s.detectThreshold;
      for (int k = 0; k < n; ++k) {
        values.push_back(s.detectThreshold * std::pow(ratio, double(k) / double(n - 1)));
      }
    }
  }
  std::vector<ThresholdLevel> levels;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0 && !(values[k] > values[k - 1])) {
      throw ConfigError("DETECT_LEVELS must increase strictly (" + std::to_string(values[k - 1]) +
                        " then " + std::to_string(values[k]) + ")");
    }
    ThresholdLevel l;
    l.level = int(k) + 1;
    l.thresholdAdu = thresholdToAdu(values[k], relative, sigmaAdu);
    // One level is a plain SExtractor run, with its own ANALYSIS_THRESH; with several, each
    // level's isophote is its detection threshold.
    l.analysisThresholdAdu =
        values.size() == 1
            ? thresholdToAdu(s.analysisThreshold,
                             s.analysisThresholdType == ThresholdType::Relative, sigmaAdu)
            : l.thresholdAdu;
    l.thresholdSigma = sigmaAdu > 0 ? l.thresholdAdu / sigmaAdu : std::nan("");
    if (!(l.thresholdAdu > 0) || !std::isfinite(l.thresholdAdu)) {
      throw ConfigError("detection threshold of level " + std::to_string(l.level) + " is " +
                        std::to_string(l.thresholdAdu) + " ADU: it must be positive");
    }
    levels.push_back(l);
  }
  return levels;
}

// Reorders the rows of `table` by (level, number).
void sortRows(Table& table, const std::vector<std::pair<int, std::int32_t>>& keys) {
  std::vector<std::size_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  Table sorted(table.columns());
  sorted.reserveRows(table.rows());
  for (std::size_t i : order) {
    double* row = sorted.appendRow();
    std::copy_n(table.row(std::int64_t(i)), table.rowWidth(), row);
  }
  table = std::move(sorted);
}

void writeCheckImages(const RunSettings& s, const PreparedImage& image,
                      const SegmentationRuns* runs, const std::vector<ThresholdLevel>& levels) {
  for (std::size_t i = 0; i < s.checkImageTypes.size(); ++i) {
    const std::string& type = s.checkImageTypes[i];
    const std::string& path = s.checkImageNames[i];
    if (type == "SEGMENTATION") {
      ImageI32 labels;
      writeImageFileSequential(path, runs->levelCount(), [&](int k, OutputImageHdu& hdu) {
        runs->render(k + 1, labels);
        hdu.header = image.hdu.header;
        hdu.header.set("THRLEVEL", std::to_string(k + 1), "octarc threshold level (1 = lowest)");
        char value[32];
        std::snprintf(value, sizeof value, "%.10G", levels[std::size_t(k)].thresholdAdu);
        hdu.header.set("THRESHLD", value, "Detection threshold of this level (ADU)");
        hdu.header.set("EXTNAME", quoteFitsString("LEVEL" + std::to_string(k + 1)));
        hdu.intPixels = &labels;
        hdu.floatPixels = nullptr;
      });
      continue;
    }
    ImageF pixels;
    if (type == "BACKGROUND") {
      pixels = image.backgroundMap ? *image.backgroundMap
                                   : ImageF(image.hdu.pixels.width(), image.hdu.pixels.height(),
                                            float(image.backgroundAdu));
    } else if (type == "BACKGROUND_RMS") {
      pixels = image.backgroundRmsMap ? *image.backgroundRmsMap
                                      : ImageF(image.hdu.pixels.width(),
                                               image.hdu.pixels.height(), float(image.sigmaAdu));
    } else if (type == "-BACKGROUND") {
      pixels = image.hdu.pixels;
    } else if (type == "FILTERED") {
      pixels = image.detectionImage();
    } else if (type == "OBJECTS") {
      // Measurement pixels on the footprints of the lowest level, 0 elsewhere.
      ImageI32 labels;
      runs->render(1, labels);
      pixels = ImageF(image.hdu.pixels.width(), image.hdu.pixels.height(), 0.0f);
      for (std::int64_t p = 0; p < pixels.size(); ++p) {
        if (labels[p] != 0) pixels[p] = image.hdu.pixels[p];
      }
    }
    OutputImageHdu hdu;
    hdu.header = image.hdu.header;
    hdu.floatPixels = &pixels;
    writeImageFile(path, {hdu});
  }
}

}  // namespace

int runDetect(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<LoadedRun> run = loadRun(args, "detect", printUsage);
  if (!run) return 0;
  const RunSettings& s = run->settings;
  if (s.imagePaths.size() != 1) {
    throw ConfigError("octarc detect takes exactly one image (got " +
                      std::to_string(s.imagePaths.size()) + "); see octarc detect -h");
  }
  if (s.catalogNames.size() != 1) throw ConfigError("CATALOG_NAME must be one file name");
  for (const std::string& t : s.checkImageTypes) {
    if (!kCheckImageTypes.count(t)) {
      throw ConfigError("CHECKIMAGE_TYPE " + t +
                        " is not supported (SEGMENTATION, BACKGROUND, BACKGROUND_RMS, "
                        "-BACKGROUND, FILTERED, OBJECTS)");
    }
  }
  const bool wantSegmentation =
      std::count(s.checkImageTypes.begin(), s.checkImageTypes.end(), "SEGMENTATION") > 0 ||
      std::count(s.checkImageTypes.begin(), s.checkImageTypes.end(), "OBJECTS") > 0;
  const bool keepMaps =
      std::count(s.checkImageTypes.begin(), s.checkImageTypes.end(), "BACKGROUND") > 0 ||
      std::count(s.checkImageTypes.begin(), s.checkImageTypes.end(), "BACKGROUND_RMS") > 0;
  const CatalogType catalogType = parseCatalogType(s.catalogType);
  const ColumnPlan columns = planColumns(s, s.quiet);
  std::optional<sexcompat::AssocSettings> assocSettings;
  if (columns.assoc) assocSettings = sexcompat::AssocSettings::fromConfig(run->config);
  const int threads = workerThreads(s.threads);

  const std::vector<std::string> extensions = listImageHdus(s.imagePaths[0]);
  const int extCount = int(extensions.size());
  std::vector<Table> tables;
  std::vector<FitsHeader> headers;
  std::vector<std::vector<std::string>> cards;
  std::vector<std::string> fits10Cards;
  tables.reserve(std::size_t(extCount));

  for (int e = 0; e < extCount; ++e) {
    if (!s.quiet) std::cerr << "> Reading " << extensions[std::size_t(e)] << "\n";
    const PreparedImage image = prepareImage(extensions[std::size_t(e)], s, {}, keepMaps);
    if (!s.quiet) {
      for (const std::string& w : image.warnings) std::cerr << "WARNING: " << w << "\n";
    }
    const std::vector<ThresholdLevel> levels = detectionLevels(s, image.sigmaAdu);
    if (!s.quiet) {
      std::cerr << "> Background " << image.backgroundAdu << " ADU (" << image.origin.background
                << "), sigma " << image.sigmaAdu << " ADU (" << image.origin.sigma << "); "
                << levels.size() << " level(s) from " << levels.front().thresholdAdu << " to "
                << levels.back().thresholdAdu << " ADU\n";
    }
    MeasureContext context = image.context(s);
    context.levels = levels;

    DetectionSettings detection;
    for (const ThresholdLevel& l : levels) detection.thresholdsAdu.push_back(l.thresholdAdu);
    detection.minArea = s.minAreaPix;
    detection.threads = threads;

    std::optional<SegmentationRuns> runs;
    if (wantSegmentation) {
      runs.emplace(image.hdu.pixels.width(), image.hdu.pixels.height(), int(levels.size()));
    }
    Table full(columns.plan.columns());
    std::vector<std::pair<int, std::int32_t>> keys;
    std::vector<Segment> batch;
    auto flush = [&]() {
      measureSegments(columns.plan, batch, context, full, threads);
      batch.clear();
    };
    const std::vector<std::int64_t> counts =
        detectMultiThreshold(image.detectionImage(), detection, [&](std::vector<Segment>& objs) {
          if (runs) runs->add(objs);
          for (Segment& o : objs) {
            keys.emplace_back(o.level, o.number);
            batch.push_back(std::move(o));
          }
          if (batch.size() >= kMeasureBatch) flush();
        });
    flush();
    sortRows(full, keys);
    if (!s.quiet) {
      for (std::size_t k = 0; k < counts.size(); ++k) {
        std::cerr << "> Level " << (k + 1) << " (" << levels[k].thresholdAdu
                  << " ADU): " << counts[k] << " objects\n";
      }
    }
    const std::int64_t detected = full.rows();
    if (assocSettings) {
      const Wcs* wcs = context.wcs;
      std::vector<std::string> warnings;
      const sexcompat::AssocList list = sexcompat::AssocList::load(
          *assocSettings, columns.assocVectorSize, image.hdu.pixels.height(),
          [wcs](double lng, double lat) {
            return wcs ? wcs->worldToPixel(lng, lat)
                       : std::array<double, 2>{std::nan(""), std::nan("")};
          },
          &warnings);
      for (const std::string& w : warnings) {
        if (!s.quiet) std::cerr << "WARNING: " << w << "\n";
      }
      applyAssoc(list, assocSettings->selection, full);
    }
    tables.push_back(outputTable(columns, full));
    headers.push_back(image.hdu.header);
    RunFacts facts;
    facts.imagePath = s.imagePaths[0];
    facts.extension = e;
    facts.extensionCount = extCount;
    facts.detectedCount = detected;
    facts.finalCount = tables.back().rows();
    facts.parameterCount = int(columns.outputColumns.size());
    facts.elapsedSec =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const RunSummary summary = runSummary(s, image, levels, facts);
    if (e == 0) fits10Cards = sexFits10Cards(summary);
    cards.push_back(runHeaderCards(summary, image, levels));
    if (!s.checkImageTypes.empty()) {
      if (extCount > 1) {
        throw ConfigError("check-images of multi-extension images are not supported yet");
      }
      writeCheckImages(s, image, runs ? &*runs : nullptr, levels);
    }
  }

  std::vector<CatalogPart> parts;
  for (int e = 0; e < extCount; ++e) {
    parts.push_back({headers[std::size_t(e)], cards[std::size_t(e)], &tables[std::size_t(e)]});
  }
  writeCatalog(s.catalogNames[0], catalogType, parts, fits10Cards);
  if (!s.quiet && catalogType != CatalogType::None) {
    std::cerr << "> Wrote " << s.catalogNames[0] << " in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
  }
  return 0;
}

}  // namespace octarc
