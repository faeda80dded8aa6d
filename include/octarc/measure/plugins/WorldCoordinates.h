// World positions and shapes (X/Y_WORLD, ALPHA/DELTA_J2000, X2/Y2/XY_WORLD, A/B/THETA_WORLD) from
// the isophotal moments, with SExtractor's finite-difference Jacobian and its formulas.
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class WorldCoordinates final : public Measurement {
 public:
  std::string name() const override { return "WorldCoordinates"; }
  std::vector<OutputColumn> columns() const override;
  std::vector<std::string> dependencies() const override { return {"IsophotalShape"}; }
  void measure(const Segment& segment, const MeasureContext& context,
               ObjectState& state) const override;
};

}  // namespace octarc
