// Object identity: NUMBER, THRESH_LEVEL, PARENT_NUMBER and the level's THRESHOLD.
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class Identity final : public Measurement {
 public:
  std::string name() const override { return "Identity"; }
  std::vector<OutputColumn> columns() const override;
};

}  // namespace octarc
