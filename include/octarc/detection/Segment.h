// One object at one threshold: a set of pixels that measurements read.
#pragma once

#include <cstdint>
#include <vector>

namespace octarc {

// One detection threshold of a (possibly single-level) run.
struct ThresholdLevel {
  int level = 1;                      // THRESH_LEVEL, 1 = lowest
  double thresholdAdu = 0.0;          // detection threshold in ADU (SEXTHLD / THRESHOLD column)
  double analysisThresholdAdu = 0.0;  // analysis threshold in ADU (ISOAREA_IMAGE), SEXATHLD
  double thresholdSigma = 0.0;  // the same in units of the global noise sigma (NaN if unknown)
};

struct Segment {
  std::int32_t number = 0;        // NUMBER: SExtractor's object number within its level (>= 1)
  int level = 1;                  // THRESH_LEVEL of this object (index into the level list + 1)
  std::int32_t parentNumber = 0;  // NUMBER of the containing object one level below; 0 at level 1
  std::vector<std::int64_t> pixels;  // linear indices y * width + x (0-based) of the footprint
};

}  // namespace octarc
