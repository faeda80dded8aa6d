#include "octarc/run/ImageRun.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/Filter.h"
#include "octarc/run/Levels.h"
#include "octarc/run/MeasurementQueue.h"

namespace octarc {

namespace {

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

DetectionSettings detectionSettings(const DetectionRequest& request) {
  DetectionSettings d;
  for (const ThresholdLevel& l : request.levels) d.thresholdsAdu.push_back(l.thresholdAdu);
  d.minArea = request.minAreaPix;
  d.threads = request.threads;
  d.footprintRuns = request.footprintRuns;
  return d;
}

}  // namespace

PreparedImage prepareInMemory(ImageF pixels, const InMemoryImage& description) {
  PreparedImage out;
  out.saturationAdu = description.saturationAdu;
  out.saturatedPixels = findSaturatedPixels(pixels, description.saturationAdu, description.threads);
  out.hdu.pixels = std::move(pixels);
  if (description.filter) {
    out.filtered = applyFilter(out.hdu.pixels, *description.filter, description.threads);
  }
  out.sigmaAdu = description.sigmaAdu;
  out.gain = description.gain;
  out.origin = {"MANUAL", "GIVEN"};
  return out;
}

Table rowsInOrder(const Table& table, const std::vector<std::int64_t>& order) {
  Table out(table.columns(), Table::Chunks::Large);
  for (const std::int64_t r : order)
    std::copy_n(table.row(r), table.rowWidth(), out.appendRowUnset());
  return out;
}

Table ImageRunResult::rowsInCatalogOrder() const {
  return rowsInOrder(rows, catalogOrder);
}

ImageRunResult detectAndMeasure(PreparedImage& image, const MeasurementPlan& plan,
                                const MeasureContext& context, const DetectionRequest& request,
                                const RunSettings* settings) {
  DetectionSettings detection = detectionSettings(request);
  // With a weight map, RELATIVE levels follow the local noise: pixel i is above level k when
  // f_i > t_k sqrt(var_i) (SEXTRACTOR.md section 4); ABSOLUTE levels stay in ADU. Bad weight
  // pixels (+Inf variance) and NaN weights never pass either way.
  const bool relative = !request.levelsInSigma.empty();
  // In dual-image mode the thresholds follow the detection image's own variance, a buffer of
  // its own that no measurement reads: it needs no restoring.
  ImageF& scale = image.thresholdVariance();
  bool scaleIsVariance = true;
  if (!scale.empty() && relative) {
    varianceToRms(scale);
    detection.thresholdScale = &scale;
    detection.thresholdsAdu = request.levelsInSigma;
    scaleIsVariance = image.separateDetection;
  } else if (!scale.empty()) {
    // ABSOLUTE levels stay in ADU; bad weight pixels are kept out by blanking them in the
    // detection image (NaN never joins an object).
    ImageF& det = image.filtered.empty() ? image.hdu.pixels : image.filtered;
    for (std::int64_t i = 0; i < det.size(); ++i) {
      if (!(scale[i] < std::numeric_limits<float>::infinity())) {
        det[i] = std::numeric_limits<float>::quiet_NaN();
      }
    }
  }
  auto restoreVariance = [&]() {
    if (scaleIsVariance) return;
    if (image.varianceFiltered) {
      if (!settings) throw Error("detectAndMeasure: a filtered variance needs the run's settings");
      image.reloadVariance(*settings);
    } else {
      rmsToVariance(image.variance);
    }
    scaleIsVariance = true;
  };

  ImageRunResult out;
  if (request.keepSegmentation) {
    out.segmentation.emplace(image.hdu.pixels.width(), image.hdu.pixels.height(),
                             int(request.levels.size()));
  }
  // Rows are appended as objects are emitted (component by component). Within a level,
  // emission order is NUMBER order, so the row indices of each level, in the order they are
  // appended, give the catalog's order.
  out.rows = Table(plan.columns(), Table::Chunks::Large);
  std::vector<std::vector<std::int64_t>> levelRows(request.levels.size());
  if (request.checkpoint) request.checkpoint();
  {
    MeasurementQueue queue(plan, context, request.threads);
    out.objectsPerLevel =
        detectMultiThreshold(image.detectionImage(), detection, [&](std::vector<Segment>& objects) {
          restoreVariance();
          if (out.segmentation) out.segmentation->add(objects);
          for (Segment& o : objects) {
            levelRows[std::size_t(o.level - 1)].push_back(out.rows.rows());
            queue.add(std::move(o), out.rows.appendRowUnset());
          }
          if (request.checkpoint) request.checkpoint();
        });
    restoreVariance();
    if (image.separateDetection) image.detectionVariance = ImageF();  // no longer needed
    queue.finish();
  }
  out.catalogOrder.reserve(std::size_t(out.rows.rows()));
  for (std::vector<std::int64_t>& rows : levelRows) {
    out.catalogOrder.insert(out.catalogOrder.end(), rows.begin(), rows.end());
    std::vector<std::int64_t>().swap(rows);
  }
  return out;
}

std::vector<Segment> detectSegments(const ImageF& detectionImage, const DetectionRequest& request) {
  DetectionSettings detection = detectionSettings(request);
  detection.footprintRuns = false;
  std::vector<Segment> segments;
  detectMultiThreshold(detectionImage, detection, [&](std::vector<Segment>& objects) {
    for (Segment& o : objects) segments.push_back(std::move(o));
  });
  std::stable_sort(segments.begin(), segments.end(), [](const Segment& a, const Segment& b) {
    return std::pair(a.level, a.number) < std::pair(b.level, b.number);
  });
  return segments;
}

std::vector<std::int64_t> countObjects(const ImageF& detectionImage,
                                       const DetectionRequest& request) {
  DetectionSettings detection = detectionSettings(request);
  detection.footprintRuns = true;
  return detectMultiThreshold(detectionImage, detection,
                              [](std::vector<Segment>& objects) { objects.clear(); });
}

DetectionRequest configuredRequest(const RunSettings& settings,
                                   const std::vector<ThresholdLevel>& levels) {
  DetectionRequest request;
  request.levels = levels;
  if (settings.detectThresholdType == ThresholdType::Relative) {
    request.levelsInSigma = levelValues(settings);
  }
  request.minAreaPix = settings.minAreaPix;
  request.threads = resolveThreads(settings.threads);
  return request;
}

}  // namespace octarc
