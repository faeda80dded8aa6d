// `octarc detect`: every threshold in one pass, no deblending, every object measured.
//
//   image --> background/noise --> (filter) --> multi-threshold detection (one pass)
//         --> measurements (per object, per level) --> catalog [+ check-images]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numeric>
#include <set>

#include "octarc/catalog/Catalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/io/FitsImage.h"
#include "octarc/pipeline/CatalogAssembly.h"
#include "octarc/pipeline/CommandLine.h"
#include "octarc/pipeline/MeasurementQueue.h"
#include "octarc/pipeline/Pipeline.h"
#include "octarc/pipeline/PreparedImage.h"
#include "octarc/pipeline/Progress.h"
#include "octarc/pipeline/RunSettings.h"

namespace octarc {

namespace {

const std::set<std::string> kCheckImageTypes = {"SEGMENTATION", "BACKGROUND", "BACKGROUND_RMS",
                                                "-BACKGROUND",  "FILTERED",   "OBJECTS"};

// clang-format off
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
      "Weight maps: WEIGHT_TYPE MAP_WEIGHT, MAP_RMS or MAP_VAR with WEIGHT_IMAGE (and\n"
      "WEIGHT_THRESH, RESCALE_WEIGHTS) as in SExtractor: RELATIVE levels become t * sqrt(var)\n"
      "per pixel, bad weight pixels never join an object, FLUXERR_ISO uses the variances.\n"
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

// The levels as given, in THRESH_TYPE units (DETECT_LEVELS, or DETECT_NLEVELS values spaced
// logarithmically from DETECT_THRESH to DETECT_THRESH_MAX), lowest first.
std::vector<double> levelValues(const RunSettings& s) {
  if (!s.detectLevels.empty()) return s.detectLevels;
  return logSpacedLevels(s.detectThreshold, s.detectThresholdMax, s.detectLevelCount);
}

// The detection levels in ADU, lowest first.
std::vector<ThresholdLevel> detectionLevels(const RunSettings& s, double sigmaAdu) {
  const bool relative = s.detectThresholdType == ThresholdType::Relative;
  const std::vector<double> values = levelValues(s);
  std::vector<ThresholdLevel> levels;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0 && !(values[k] > values[k - 1])) {
      char text[96];
      std::snprintf(text, sizeof text, "DETECT_LEVELS: levels must increase strictly (%g then %g)",
                    values[k - 1], values[k]);
      throw ConfigError(text);
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

// A copy of `table` holding its rows in `order`.
Table rowsInOrder(const Table& table, const std::vector<std::int64_t>& order) {
  Table out(table.columns(), Table::Chunks::Large);
  for (const std::int64_t r : order)
    std::copy_n(table.row(r), table.rowWidth(), out.appendRowUnset());
  return out;
}

// The variance map and the detector's per-pixel threshold factor share one buffer: the
// detector reads the factor only in its first scan over the image, before it hands out any
// object, so the buffer is turned back into variances before the first measurement.
//
// SExtractor's per-pixel threshold is DETECT_THRESH * sqrt(var_i) in single precision, not
// (DETECT_THRESH * sigma) * sqrt(var_i) / sigma, whose extra roundings move pixels lying on the
// threshold. So the detector is given the levels in sigma units and the factor sqrt(var_i):
// t_k * sqrt(var_i) is the same threshold in ADU, rounded as SExtractor rounds it.
void varianceToRms(ImageF& buffer) {
  for (float& v : buffer.pixels()) v = float(std::sqrt(double(v)));
}

void rmsToVariance(ImageF& buffer) {
  for (float& v : buffer.pixels()) v = float(double(v) * double(v));
}

// Human-readable size of a file, for progress lines ("6.0 GB").
std::string sizeText(const std::string& path) {
  std::error_code ec;
  const double bytes = double(std::filesystem::file_size(path, ec));
  if (ec) return "?";
  char text[32];
  if (bytes >= 1e9) {
    std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
  } else {
    std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  }
  return text;
}

// Writes the check images once everything else has succeeded, each at its temporary name in
// `outputs` (check image i is output firstCheck + i) and each through at most one image-sized
// buffer. OBJECTS goes last: it blanks the measurement image in place.
void writeCheckImages(const RunSettings& s, PreparedImage& image, const SegmentationRuns* runs,
                      const std::vector<ThresholdLevel>& levels, const OutputFiles& outputs,
                      std::size_t firstCheck) {
  // Measurements are done: free the buffers no check image needs, to make room for the one
  // image-sized buffer the check images use.
  image.variance = ImageF();
  if (std::count(s.checkImageTypes.begin(), s.checkImageTypes.end(), "FILTERED") == 0) {
    image.filtered = ImageF();
  }
  auto writeFloat = [&](const std::string& path, const ImageF& pixels) {
    OutputImageHdu hdu;
    hdu.header = image.hdu.header;
    hdu.floatPixels = &pixels;
    writeImageFile(path, {hdu});
  };
  // A line when each check image is done: the multi-level ones take a while (6 GB for 15 levels
  // of a 10000^2 image).
  auto done = [&](std::size_t i, std::chrono::steady_clock::time_point since) {
    if (s.quiet) return;
    std::cerr << "> Wrote check-image " << s.checkImageNames[i] << " (" << s.checkImageTypes[i]
              << ", " << sizeText(outputs[firstCheck + i].tempPath()) << ") in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count()
              << " s\n";
  };
  for (std::size_t i = 0; i < s.checkImageTypes.size(); ++i) {
    const std::string& type = s.checkImageTypes[i];
    if (type == "OBJECTS") continue;
    const auto since = std::chrono::steady_clock::now();
    outputs.write(firstCheck + i, [&](const std::string& path) {
      if (type == "SEGMENTATION") {
        ImageI32 labels;
        const ProgressFn progress =
            terminalProgress("writing " + s.checkImageNames[i], "levels", s.quiet);
        writeImageFileSequential(path, runs->levelCount(), [&](int k, OutputImageHdu& hdu) {
          if (progress) progress(k, runs->levelCount());
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
        if (progress) progress(runs->levelCount(), runs->levelCount());
      } else if (type == "BACKGROUND") {
        // A map read from a file is written as it is, not copied first.
        if (image.backgroundMap) {
          writeFloat(path, *image.backgroundMap);
        } else {
          writeFloat(path, image.backgroundImage());
        }
      } else if (type == "BACKGROUND_RMS") {
        if (image.backgroundRmsMap) {
          writeFloat(path, *image.backgroundRmsMap);
        } else {
          writeFloat(path, image.backgroundRmsImage());
        }
      } else if (type == "-BACKGROUND") {
        writeFloat(path, image.hdu.pixels);
      } else if (type == "FILTERED") {
        writeFloat(path, image.detectionImage());
      }
    });
    done(i, since);
  }
  bool blanked = false;
  for (std::size_t i = 0; i < s.checkImageTypes.size(); ++i) {
    if (s.checkImageTypes[i] != "OBJECTS") continue;
    const auto since = std::chrono::steady_clock::now();
    if (!blanked) {
      // Measurement pixels on the footprints of the lowest level, 0 elsewhere.
      ImageI32 labels;
      runs->render(1, labels);
      ImageF& pixels = image.hdu.pixels;
      for (std::int64_t p = 0; p < pixels.size(); ++p) {
        if (labels[p] == 0) pixels[p] = 0.0f;
      }
      blanked = true;
    }
    outputs.write(firstCheck + i,
                  [&](const std::string& path) { writeFloat(path, image.hdu.pixels); });
    done(i, since);
  }
}

}  // namespace

int runDetect(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<LoadedRun> run = loadRun(args, "detect", printUsage);
  if (!run) return 0;
  const RunSettings& s = run->settings;
  requireSingleImage(s, "detect");
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
  const int threads = resolveThreads(s.threads);

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

  const std::vector<std::string> extensions = listImageHdus(s.imagePaths[0]);
  const int extCount = int(extensions.size());
  if (!s.checkImageTypes.empty() && extCount > 1) {
    throw ConfigError("CHECKIMAGE_TYPE: check-images of multi-extension images are not supported");
  }
  // The single image and its footprints, kept for the check images written after the catalog.
  std::optional<PreparedImage> checkImage;
  std::optional<SegmentationRuns> checkRuns;
  std::vector<ThresholdLevel> checkLevels;
  std::vector<Table> tables;                      // per extension: its rows, as measured
  std::vector<std::vector<std::int64_t>> orders;  // per extension: the catalog's row order
  std::vector<FitsHeader> headers;
  std::vector<std::vector<std::string>> cards;
  std::vector<std::string> fits10Cards;
  tables.reserve(std::size_t(extCount));

  // VERBOSE_TYPE FULL reports where the time goes.
  auto lap = [&, last = std::chrono::steady_clock::now()](const char* stage) mutable {
    const auto now = std::chrono::steady_clock::now();
    if (s.verboseFull) {
      std::cerr << "> Time: " << stage << " " << std::chrono::duration<double>(now - last).count()
                << " s\n";
    }
    last = now;
  };

  for (int e = 0; e < extCount; ++e) {
    if (!s.quiet) std::cerr << "> Reading " << extensions[std::size_t(e)] << "\n";
    const bool relative = s.detectThresholdType == ThresholdType::Relative;
    const RunSettings extensionSettings = settingsForExtension(s, e, extCount);
    PreparedImage image =
        prepareImage(extensions[std::size_t(e)], extensionSettings, {}, keepMaps, relative);
    if (!s.quiet) {
      for (const std::string& w : image.warnings) std::cerr << "WARNING: " << w << "\n";
    }
    lap("reading, background and filtering");
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
    detection.footprintRuns = true;
    // With a weight map, RELATIVE levels follow the local noise: pixel i is above level k when
    // f_i > t_k sqrt(var_i) (SEXTRACTOR.md section 4); ABSOLUTE levels stay in ADU. Bad weight
    // pixels (+Inf variance) and NaN weights never pass either way.
    const bool scaled = !image.variance.empty() && relative;
    bool scaleIsVariance = true;
    if (scaled) {
      varianceToRms(image.variance);
      detection.thresholdScale = &image.variance;
      detection.thresholdsAdu = levelValues(s);
      scaleIsVariance = false;
    } else if (!image.variance.empty()) {
      // ABSOLUTE levels stay in ADU; bad weight pixels are kept out by blanking them in the
      // detection image (NaN never joins an object).
      ImageF& det = image.filtered.empty() ? image.hdu.pixels : image.filtered;
      for (std::int64_t i = 0; i < det.size(); ++i) {
        if (!(image.variance[i] < std::numeric_limits<float>::infinity())) {
          det[i] = std::numeric_limits<float>::quiet_NaN();
        }
      }
    }
    auto restoreVariance = [&]() {
      if (scaleIsVariance) return;
      if (image.varianceFiltered) {
        image.reloadVariance(extensionSettings);
      } else {
        rmsToVariance(image.variance);
      }
      scaleIsVariance = true;
    };

    std::optional<SegmentationRuns> runs;
    if (wantSegmentation) {
      runs.emplace(image.hdu.pixels.width(), image.hdu.pixels.height(), int(levels.size()));
    }
    // Rows are appended as objects are emitted (component by component); the catalog lists
    // them level by level. Within a level, emission order is NUMBER order, so the row indices
    // of each level, in the order they are appended, give the catalog's order.
    Table full(columns.plan.columns(), Table::Chunks::Large);
    std::vector<std::vector<std::int64_t>> levelRows(levels.size());
    std::vector<std::int64_t> counts;
    {
      MeasurementQueue queue(columns.plan, context, threads);
      counts =
          detectMultiThreshold(image.detectionImage(), detection, [&](std::vector<Segment>& objs) {
            restoreVariance();
            if (runs) runs->add(objs);
            for (Segment& o : objs) {
              levelRows[std::size_t(o.level - 1)].push_back(full.rows());
              queue.add(std::move(o), full.appendRowUnset());
            }
          });
      restoreVariance();
      queue.finish();
    }
    lap("detection and measurement");
    if (!s.quiet) {
      for (std::size_t k = 0; k < counts.size(); ++k) {
        std::cerr << "> Level " << (k + 1) << " (" << levels[k].thresholdAdu
                  << " ADU): " << counts[k] << " objects\n";
      }
    }
    std::vector<std::int64_t> order;
    order.reserve(std::size_t(full.rows()));
    for (std::vector<std::int64_t>& rows : levelRows) {
      order.insert(order.end(), rows.begin(), rows.end());
      std::vector<std::int64_t>().swap(rows);
    }
    const std::int64_t detected = full.rows();
    if (assocSettings) {
      // ASSOC removes rows: put them in catalog order first.
      full = rowsInOrder(full, order);
      order.clear();
      applyAssoc(*assocSettings, columns.assocVectorSize, image, full, s.quiet);
    }
    tables.push_back(outputTable(columns, std::move(full)));
    const std::int64_t kept = tables.back().rows();
    orders.push_back(std::move(order));
    headers.push_back(image.hdu.header);
    RunFacts facts;
    facts.imagePath = s.imagePaths[0];
    facts.extension = e;
    facts.extensionCount = extCount;
    facts.detectedCount = detected;
    facts.finalCount = kept;
    facts.parameterCount = int(columns.outputColumns.size());
    facts.elapsedSec =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    RunSummary summary = runSummary(s, image, levels, facts);
    if (!image.variance.empty()) {
      summary.detectWeightScale = image.weightScale;
      summary.measureWeightScale = image.weightScale;
    }
    if (e == 0) fits10Cards = sexFits10Cards(summary);
    cards.push_back(runHeaderCards(summary, image, levels));
    if (!s.checkImageTypes.empty()) {
      checkImage = std::move(image);
      checkRuns = std::move(runs);
      checkLevels = levels;
    }
  }

  std::vector<CatalogPart> parts;
  for (int e = 0; e < extCount; ++e) {
    const std::vector<std::int64_t>& order = orders[std::size_t(e)];
    parts.push_back({headers[std::size_t(e)], cards[std::size_t(e)], &tables[std::size_t(e)],
                     order.empty() ? nullptr : &order});
  }
  lap("assembling the catalog");
  if (catalogType != CatalogType::None) {
    outputs.write(
        0, [&](const std::string& path) { writeCatalog(path, catalogType, parts, fits10Cards); });
  }
  lap("writing the catalog");
  if (!s.quiet && catalogType != CatalogType::None) {
    std::cerr << "> Wrote " << s.catalogNames[0] << " in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
  }
  // Check images last. The catalog is written: its rows make room for their buffer.
  parts.clear();
  std::vector<Table>().swap(tables);
  std::vector<std::vector<std::int64_t>>().swap(orders);
  if (checkImage) {
    writeCheckImages(s, *checkImage, checkRuns ? &*checkRuns : nullptr, checkLevels, outputs,
                     firstCheck);
  }
  // Every output is complete: they appear together.
  outputs.commit();
  return 0;
}

}  // namespace octarc
