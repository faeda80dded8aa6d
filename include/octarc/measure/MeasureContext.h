// Everything a measurement may read besides the object's pixels. Owned by the caller; all
// pointers outlive the measurement pass.
#pragma once

#include <cstdint>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"

namespace octarc {

class Wcs;

struct MeasureContext {
  // Background-subtracted, unfiltered measurement image (p_i in SEXTRACTOR.md §3).
  const ImageF* measurement = nullptr;
  // Filtered, background-subtracted detection image (f_i). Equal to `measurement` with FILTER N.
  const ImageF* detection = nullptr;
  // Linear indices, ascending, of the pixels whose raw value (before background subtraction)
  // is at or above SATUR_LEVEL; an object holding one gets FLAGS bit 4. nullptr: none.
  const std::vector<std::int64_t>* saturatedPixels = nullptr;
  // Optional per-pixel variance (ADU^2); nullptr means the global sigma for every pixel.
  const ImageF* variance = nullptr;

  double sigmaAdu = 0.0;          // global background noise (SEXBKDEV)
  double gain = 0.0;              // e-/ADU; 0 = infinite (no Poisson term)
  double magZeropoint = 0.0;      // MAG_ZEROPOINT
  double pixelScaleArcsec = 0.0;  // PIXEL_SCALE; 0 = from the WCS
  const Wcs* wcs = nullptr;       // celestial WCS or nullptr

  std::vector<ThresholdLevel> levels;  // levels[segment.level - 1]
};

}  // namespace octarc
