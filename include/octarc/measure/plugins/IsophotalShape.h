// SExtractor isophotal position and shape (X_IMAGE ... ELLIPTICITY, XPEAK/YPEAK_IMAGE), weighted by
// the detection image (the filtered image when FILTER Y), as SEXTRACTOR.md §3 describes.
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class IsophotalShape final : public Measurement {
 public:
  std::string name() const override { return "IsophotalShape"; }
  std::vector<OutputColumn> columns() const override;
  std::vector<std::string> dependencies() const override { return {"Footprint"}; }
  void measure(const Segment& segment, const MeasureContext& context,
               ObjectState& state) const override;
};

}  // namespace octarc
