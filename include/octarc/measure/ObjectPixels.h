// The pixels of one object, gathered once per object for every measurement to loop over.
//
// A footprint is a list of linear indices y * width + x. Splitting them into (x, y) and reading
// the images at them once, here, rather than once per measurement, keeps the per-pixel work of
// a measurement to plain arithmetic over contiguous arrays (the catalogs of `octarc detect` hold
// every pixel above the lowest level once per level it exceeds).
#pragma once

#include <cstddef>
#include <vector>

#include "octarc/core/Segment.h"
#include "octarc/measure/MeasureContext.h"

namespace octarc {

struct ObjectPixels {
  // 0-based pixel coordinates (core/Conventions.h), in footprint order.
  std::vector<double> x, y;
  // Measurement image p_i (background-subtracted, unfiltered).
  std::vector<double> value;
  // Detection image f_i (the filtered image with FILTER Y): see detectionValues().
  std::vector<double> detection;
  // Per-pixel variance; empty when the context has no variance map.
  std::vector<double> variance;
  // True when every value[i] is finite (the usual case; measurements then skip their checks).
  bool valuesFinite = true;

  std::size_t size() const { return x.size(); }
  // f_i: `detection`, or `value` itself when the detection image is the measurement image.
  const std::vector<double>& detectionValues() const {
    return separateDetection ? detection : value;
  }
  bool separateDetection = false;

  // Fills the arrays for `segment` (pixel indices in any order; ascending is fastest), reusing
  // the vectors' storage from one object to the next.
  void gather(const Segment& segment, const MeasureContext& context);
};

}  // namespace octarc
