// The octopole arc statistics of METHOD.md §1 (ARCNESS, ANTIARCNESS, SKEW_MAJOR/MINOR, I_*_IMAGE,
// ARC_SIDE, E1/E2/E_IMAGE, SIZE_IMAGE), always from the unfiltered measurement image.
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class Octopole final : public Measurement {
 public:
  std::string name() const override { return "Octopole"; }
  std::vector<OutputColumn> columns() const override;
  void measure(const Segment& segment, const MeasureContext& context,
               ObjectState& state) const override;
};

}  // namespace octarc
