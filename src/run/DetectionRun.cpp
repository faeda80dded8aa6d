#include "octarc/run/DetectionRun.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Progress.h"
#include "octarc/io/FitsImage.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/RunKeys.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

namespace {

bool wants(const RunSettings& s, const char* type) {
  return std::count(s.checkImageTypes.begin(), s.checkImageTypes.end(), type) > 0;
}

double secondsSince(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
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

// Writes one multi-level SEGMENTATION check-image, an int32 HDU per level.
void writeSegmentation(const std::string& path, const std::string& name,
                       const DetectionRunResult& result, bool quiet) {
  const SegmentationRuns& runs = *result.segmentation;
  ImageI32 labels;
  const ProgressFn progress = terminalProgress("writing " + name, "levels", quiet);
  writeImageFileSequential(path, runs.levelCount(), [&](int k, OutputImageHdu& hdu) {
    if (progress) progress(k, runs.levelCount());
    runs.render(k + 1, labels);
    hdu.header = result.checkImage->hdu.header;
    hdu.header.set("THRLEVEL", std::to_string(k + 1), "octarc threshold level (1 = lowest)");
    char value[32];
    std::snprintf(value, sizeof value, "%.10G", result.checkLevels[std::size_t(k)].thresholdAdu);
    hdu.header.set("THRESHLD", value, "Detection threshold of this level (ADU)");
    hdu.header.set("EXTNAME", quoteFitsString("LEVEL" + std::to_string(k + 1)));
    hdu.intPixels = &labels;
    hdu.floatPixels = nullptr;
  });
  if (progress) progress(runs.levelCount(), runs.levelCount());
}

// Detects and measures one image extension (`e` of `count`).
DetectedExtension detectExtension(const RunSettings& s, const ColumnPlan& columns,
                                  const std::optional<sexcompat::AssocSettings>& assoc,
                                  const std::string& path, int e, int count,
                                  std::chrono::steady_clock::time_point start, StageClock& clock,
                                  DetectionRunResult& result, const RunLog& log, bool keep) {
  const bool checkImages = !s.checkImageTypes.empty() || keep;
  const bool keepMaps = wants(s, "BACKGROUND") || wants(s, "BACKGROUND_RMS");
  const bool relative = s.detectThresholdType == ThresholdType::Relative;
  const RunSettings extensionSettings = settingsForExtension(s, e, count);
  if (log) {
    log(s.dualImage()
            ? "> Reading " + extensionSettings.detectionImagePath() + " (detection) and " +
                  extensionSettings.measurementImagePath() + " (measurement)"
            : "> Reading " + path);
  }
  PreparedImage image = prepareRunImage(s, e, count, keepMaps, relative);
  if (log) {
    for (const std::string& w : image.warnings) log("WARNING: " + w);
  }
  clock.lap("reading, background and filtering");
  DetectedExtension out;
  out.levels =
      detectionLevels(s, image.detectionSigma(), image.separateDetection ? image.sigmaAdu : 0.0);
  const std::vector<ThresholdLevel>& levels = out.levels;
  if (log) {
    std::ostringstream line;
    line << "> Background " << image.backgroundAdu << " ADU (" << image.origin.background
         << "), sigma " << image.sigmaAdu << " ADU (" << image.origin.sigma << "); ";
    if (image.separateDetection) {
      line << "detection image sigma " << image.detectionSigma() << " ADU; ";
    }
    line << levels.size() << " level(s) from " << levels.front().thresholdAdu << " to "
         << levels.back().thresholdAdu << " ADU";
    log(line.str());
  }
  MeasureContext context = image.context(s);
  context.levels = levels;

  DetectionRequest request = configuredRequest(s, levels);
  request.keepSegmentation =
      keep || (checkImages && (wants(s, "SEGMENTATION") || wants(s, "OBJECTS")));
  ImageRunResult run = detectAndMeasure(image, columns.plan, context, request, &extensionSettings);
  out.objectsPerLevel = run.objectsPerLevel;
  clock.lap("detection and measurement");
  if (log) {
    for (std::size_t k = 0; k < run.objectsPerLevel.size(); ++k) {
      std::ostringstream line;
      line << "> Level " << (k + 1) << " (" << levels[k].thresholdAdu
           << " ADU): " << run.objectsPerLevel[k] << " objects";
      log(line.str());
    }
  }
  const std::int64_t detected = run.rows.rows();
  Table full = std::move(run.rows);
  if (assoc) {
    // ASSOC removes rows: put them in catalog order first.
    full = rowsInOrder(full, run.catalogOrder);
    run.catalogOrder.clear();
    applyAssoc(*assoc, columns.assocVectorSize, image, full, s.quiet);
  }
  out.table = outputTable(columns, std::move(full));
  out.order = std::move(run.catalogOrder);
  out.header = image.hdu.header;

  RunFacts facts;
  facts.imagePath = s.measurementImagePath();  // FITSFILE: the measured image, as SExtractor
  facts.extension = e;
  facts.extensionCount = count;
  facts.detectedCount = detected;
  facts.finalCount = out.table.rows();
  facts.parameterCount = int(columns.outputColumns.size());
  facts.elapsedSec = secondsSince(start);
  RunSummary summary = runSummary(s, image, levels, facts);
  if (image.separateDetection) {
    const bool detectionWeights = s.weightType != WeightType::None;
    if (detectionWeights) summary.detectWeightScale = image.detectionWeightScale;
    if (!image.variance.empty()) summary.measureWeightScale = image.weightScale;
  } else if (!image.variance.empty()) {
    summary.detectWeightScale = image.weightScale;
    summary.measureWeightScale = image.weightScale;
  }
  if (e == 0) result.fits10Cards = sexFits10Cards(summary);
  out.cards = runHeaderCards(summary, image, levels);
  out.summary = summary;
  if (checkImages) {
    result.checkImage = std::move(image);
    result.segmentation = std::move(run.segmentation);
    result.checkLevels = levels;
  }
  return out;
}

}  // namespace

const std::vector<std::string>& detectCheckImageTypes() {
  static const std::vector<std::string> types = {"SEGMENTATION", "BACKGROUND", "BACKGROUND_RMS",
                                                 "-BACKGROUND",  "FILTERED",   "OBJECTS"};
  return types;
}

std::vector<CatalogPart> DetectionRunResult::parts() const {
  std::vector<CatalogPart> out;
  for (const DetectedExtension& x : extensions) {
    out.push_back({x.header, x.cards, &x.table, x.order.empty() ? nullptr : &x.order});
  }
  return out;
}

DetectionRunResult runDetection(const RunSettings& s, const ColumnPlan& columns,
                                const std::optional<sexcompat::AssocSettings>& assoc,
                                const RunLog& log, bool keepImageAndFootprints) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> extensions = listImageHdus(s.detectionImagePath());
  const int count = int(extensions.size());
  if (!s.checkImageTypes.empty() && count > 1) {
    throw ConfigError("CHECKIMAGE_TYPE: check-images of multi-extension images are not supported");
  }
  if (keepImageAndFootprints && count > 1) {
    throw ConfigError(s.imagePaths[0] +
                      ": a multi-extension image; search one extension at a "
                      "time (image.fits[N])");
  }
  DetectionRunResult result;
  result.extensions.reserve(std::size_t(count));
  StageClock clock(s.verboseFull, log);
  for (int e = 0; e < count; ++e) {
    result.extensions.push_back(detectExtension(s, columns, assoc, extensions[std::size_t(e)], e,
                                                count, start, clock, result, log,
                                                keepImageAndFootprints));
  }
  return result;
}

DetectionRunResult runConfiguredDetection(
    const std::string& imagePath, const std::string& configPath,
    const std::vector<std::pair<std::string, std::string>>& keys) {
  std::vector<std::string> warnings;
  const sexcompat::Config config =
      sexcompat::Config::load(octarcKeys(), configPath, keys, &warnings);
  RunSettings settings = settingsFromConfig(config);
  settings.imagePaths = {imagePath};
  settings.configPath = configPath;
  const ColumnPlan columns =
      planColumns(settings, true, int(detectionLevels(settings, 1.0).size()));
  std::optional<sexcompat::AssocSettings> assoc;
  if (columns.assoc) assoc = sexcompat::AssocSettings::fromConfig(config);
  return runDetection(settings, columns, assoc, RunLog());
}

void writeCheckImages(const RunSettings& s, DetectionRunResult& result, const OutputFiles& outputs,
                      std::size_t firstCheck, const RunLog& log) {
  if (!result.checkImage) return;
  PreparedImage& image = *result.checkImage;
  // Measurements are done: free the buffers no check image needs, to make room for the one
  // image-sized buffer the check images use.
  image.variance = ImageF();
  if (!wants(s, "FILTERED")) image.filtered = ImageF();
  auto writeFloat = [&](const std::string& path, const ImageF& pixels) {
    OutputImageHdu hdu;
    hdu.header = image.hdu.header;
    hdu.floatPixels = &pixels;
    writeImageFile(path, {hdu});
  };
  // A line when each check image is done: the multi-level ones take a while (6 GB for 15 levels
  // of a 10000^2 image).
  auto done = [&](std::size_t i, std::chrono::steady_clock::time_point since) {
    if (!log) return;
    std::ostringstream line;
    line << "> Wrote check-image " << s.checkImageNames[i] << " (" << s.checkImageTypes[i] << ", "
         << sizeText(outputs[firstCheck + i].tempPath()) << ") in " << secondsSince(since) << " s";
    log(line.str());
  };
  for (std::size_t i = 0; i < s.checkImageTypes.size(); ++i) {
    const std::string& type = s.checkImageTypes[i];
    if (type == "OBJECTS") continue;
    const auto since = std::chrono::steady_clock::now();
    outputs.write(firstCheck + i, [&](const std::string& path) {
      if (type == "SEGMENTATION") {
        writeSegmentation(path, s.checkImageNames[i], result, s.quiet);
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
      result.segmentation->render(1, labels);
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

}  // namespace octarc
