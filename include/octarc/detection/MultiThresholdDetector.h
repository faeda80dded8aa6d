// Detection at many thresholds in one pass, without deblending or cleaning: at every level the
// objects are exactly SExtractor's with FILTER as given, DEBLEND_NTHRESH 1, CLEAN N (8-connected
// pixels strictly above the threshold, at least DETECT_MINAREA of them), and each object knows
// the object one level below that contains it.
//
// How (see PERFORMANCE.md): one streaming pass (row bands in parallel) finds the runs of pixels
// above the lowest level and, for each of their pixels, the number of levels it exceeds (one
// byte); a run-based union-find labels the runs into connected components. Each component is
// then handled on its own (components in parallel): level by level, the runs of the objects kept
// at the level below are cut into the runs of the next level and labelled again, so work is
// spent only inside objects that survived DETECT_MINAREA. No full-frame label or level array is
// allocated: memory beyond the input is about 28 bytes per lowest-level run plus one byte per
// pixel above the lowest level, plus the objects of the components in flight.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"

namespace octarc {

struct DetectionSettings {
  // Detection thresholds in ADU (of the detection image), strictly increasing, at most
  // kMaxThresholdLevels; level k + 1 = thresholdsAdu[k].
  std::vector<double> thresholdsAdu;
  // DETECT_MINAREA: objects with fewer pixels are dropped (their pixels stay in the parent).
  int minArea = 5;
  // Optional per-pixel threshold factor (weight maps), same size as the image: pixel i is above
  // level k when f_i > thresholdsAdu[k] * scale_i. A factor <= 0 or NaN keeps the pixel out.
  const ImageF* thresholdScale = nullptr;
  // Worker threads (<= 0: all hardware threads). Results do not depend on it.
  int threads = 1;
  // Footprints as Segment::runs (raster order, `pixels` left empty) instead of pixel lists.
  bool footprintRuns = false;
};

// Detects every level and calls `sink` once per lowest-level component that has at least one
// kept object, with all its objects at every level (ordered by level, then NUMBER). Calls are
// serialised, on the calling thread, in an order independent of `threads`: components by their
// first pixel in raster order (y, then x). NUMBER counts within each level (1, 2, ... in the order
// of emission; inside a component, by first pixel in raster order); parentNumber is the NUMBER of
// the level-below object that contains the object (0 at level 1). Pixel lists are ascending
// linear indices y * width + x (or, with footprintRuns, runs in raster order). The sink may move
// from or clear `objects`.
//
// Pixels that are NaN or infinite never join an object. As in SExtractor, comparisons are in
// single precision: f > (float)threshold, or f > (float)threshold * scale (float product).
//
// Returns the number of objects per level. Throws ConfigError (one line, naming the option) for
// no thresholds, thresholds not strictly increasing or not finite, more than kMaxThresholdLevels
// levels, DETECT_MINAREA < 1, or a threshold scale map whose size differs from the image's. An
// image without any pixel above the lowest level (all NaN, constant below it) gives no objects.
std::vector<std::int64_t> detectMultiThreshold(
    const ImageF& detection, const DetectionSettings& settings,
    const std::function<void(std::vector<Segment>& objects)>& sink);

// The footprints of all objects of all levels kept as horizontal runs (16 bytes per run, far
// less than pixel lists or one int32 image per level), so that a pipeline can write one
// SExtractor SEGMENTATION image per level, one after another, through a single int32 buffer:
//
//   SegmentationRuns runs(width, height, nLevels);
//   detectMultiThreshold(image, settings, [&](std::vector<Segment>& objs) {
//     runs.add(objs);  /* ... measure ... */ });
//   ImageI32 buffer;
//   for (int level = 1; level <= nLevels; ++level) { runs.render(level, buffer); /* write */ }
class SegmentationRuns {
 public:
  SegmentationRuns(std::int64_t width, std::int64_t height, int levelCount);

  // Records objects (any level in 1..levelCount; pixel lists in any order; number > 0).
  void add(const std::vector<Segment>& objects);

  // Sets `labels` to the SEGMENTATION image of `level` (1-based): each pixel holds the NUMBER of
  // the object of that level covering it, 0 elsewhere. `labels` is reused when already
  // width x height, so one buffer serves every level.
  void render(int level, ImageI32& labels) const;

  std::int64_t width() const { return width_; }
  std::int64_t height() const { return height_; }
  int levelCount() const { return static_cast<int>(levels_.size()); }
  // Runs stored for `level` (memory use: 16 bytes each).
  std::size_t runCount(int level) const;
  // The footprints of objects `numbers` of `level` (one pass over the level's runs), each in
  // raster order; empty for a number with no object.
  std::vector<std::vector<PixelRun>> footprints(int level,
                                                const std::vector<std::int32_t>& numbers) const;

 private:
  struct Run {
    std::int32_t y;
    std::int32_t x0;      // first pixel
    std::int32_t length;  // pixels
    std::int32_t number;  // NUMBER of the object
  };
  std::int64_t width_ = 0;
  std::int64_t height_ = 0;
  std::vector<std::vector<Run>> levels_;
};

}  // namespace octarc
