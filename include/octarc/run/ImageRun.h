// Detection and measurement of one image, in memory: the run API that `octarc detect`, the
// lens simulator, the source-database builder, the demo and the Python module share.
//
//   PreparedImage (from a file: prepareImage; from memory: prepareInMemory)
//     --> detectAndMeasure(image, plan, context, request)
//     --> ImageRunResult: per-level rows (+ segmentation labels on request)
//
// Nothing here touches the disk: catalogs and check-images are written by the caller
// (run/DetectionRun.h for a whole configured run).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "octarc/core/ConvKernel.h"
#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"
#include "octarc/core/Table.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/measure/MeasureContext.h"
#include "octarc/measure/Registry.h"
#include "octarc/run/PreparedImage.h"

namespace octarc {

// An image already in memory, background-subtracted, with known noise (a simulated stamp).
struct InMemoryImage {
  double sigmaAdu = 0.0;               // global noise sigma
  double gain = 0.0;                   // e-/ADU, 0 = infinite
  double saturationAdu = 0.0;          // pixels at or above it are saturated; <= 0: none
  const ConvKernel* filter = nullptr;  // detection filter, or none
  int threads = 1;                     // for the filter and the saturation scan
};

// A PreparedImage holding `pixels` (moved in) as its measurement image, the filtered detection
// image when `description.filter` is set, and its saturated pixels; no WCS, no weight map.
PreparedImage prepareInMemory(ImageF pixels, const InMemoryImage& description);

// What to detect.
struct DetectionRequest {
  std::vector<ThresholdLevel> levels;  // in ADU, lowest first (run/Levels.h)
  // THRESH_TYPE RELATIVE: the levels in units of the noise sigma as the configuration gives
  // them. With a weight map they become per-pixel thresholds t_k * sqrt(var_i), rounded as
  // SExtractor rounds them; empty for ABSOLUTE levels, which stay in ADU.
  std::vector<double> levelsInSigma;
  int minAreaPix = 5;             // DETECT_MINAREA
  int threads = 1;                // detection and measurement threads; the rows do not depend on it
  bool keepSegmentation = false;  // fill ImageRunResult::segmentation
  // Footprints handed to the measurements as pixel runs rather than pixel lists (less memory
  // for large images; the same measured values).
  bool footprintRuns = true;
  // Called on the calling thread before the detection and after each connected component's
  // objects are queued for measurement (an embedding program's chance to see an interrupt, e.g.
  // Python's Ctrl-C); an exception thrown there abandons the run: every worker is joined and it
  // propagates out of detectAndMeasure. Empty: never called.
  std::function<void()> checkpoint;
};

// The request of a configured run at `levels`: the thresholds per pixel with THRESH_TYPE
// RELATIVE, DETECT_MINAREA and NTHREADS of `settings` (no segmentation kept, no checkpoint).
DetectionRequest configuredRequest(const RunSettings& settings,
                                   const std::vector<ThresholdLevel>& levels);

struct ImageRunResult {
  // One row per object per level (the plan's columns), in the order the detector emitted them
  // (component by component).
  Table rows;
  // Row indices in catalog order: level by level, NUMBER order within a level.
  std::vector<std::int64_t> catalogOrder;
  std::vector<std::int64_t> objectsPerLevel;
  std::optional<SegmentationRuns> segmentation;  // every level's labels, when asked

  // The rows in catalog order (a copy).
  Table rowsInCatalogOrder() const;
};

// A copy of `table` holding its rows in `order`.
Table rowsInOrder(const Table& table, const std::vector<std::int64_t>& order);

// Detects `image` at every level of `request` in one pass and measures every object with
// `plan` in `context` (image.context(), with the levels filled). A weight map's variance buffer
// is used as the per-pixel threshold scale during the first scan and restored before the first
// measurement (a filtered variance is read again from the weight map of `settings`). In dual-image
// mode the thresholds follow the detection image's variance instead, left as an RMS map.
ImageRunResult detectAndMeasure(PreparedImage& image, const MeasurementPlan& plan,
                                const MeasureContext& context, const DetectionRequest& request,
                                const RunSettings* settings = nullptr);

// Detection alone: every object of every level, ordered by level then NUMBER, with pixel lists
// (for code that cuts the objects out rather than measuring them).
std::vector<Segment> detectSegments(const ImageF& detectionImage, const DetectionRequest& request);

// Detection alone, counting: the objects of every level (DETECT_MINAREA pixels or more), lowest
// level first, without keeping any (noise-only studies run it thousands of times).
std::vector<std::int64_t> countObjects(const ImageF& detectionImage,
                                       const DetectionRequest& request);

}  // namespace octarc
