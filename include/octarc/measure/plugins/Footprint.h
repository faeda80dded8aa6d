// Footprint geometry and SExtractor FLAGS: bounding box, ISOAREAF_IMAGE, saturated (4) and
// border (8) bits.
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class Footprint final : public Measurement {
 public:
  std::string name() const override { return "Footprint"; }
  std::vector<OutputColumn> columns() const override;
  void measure(const Segment& segment, const MeasureContext& context,
               ObjectState& state) const override;
};

}  // namespace octarc
