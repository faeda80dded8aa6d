// OCT_FLAGS: the octarc flag bits (core/Flags.h) collected from the measurements that ran before.
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class QualityFlags final : public Measurement {
 public:
  std::string name() const override { return "QualityFlags"; }
  std::vector<OutputColumn> columns() const override;
  std::vector<std::string> dependencies() const override {
    return {"Footprint", "IsophotalShape", "IsophotalPhotometry", "Octopole"};
  }
};

}  // namespace octarc
