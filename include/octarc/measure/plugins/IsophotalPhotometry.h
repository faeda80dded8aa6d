// Isophotal photometry on the measurement image: ISOAREA_IMAGE, FLUX_ISO, FLUXERR_ISO, MAG_ISO,
// MAGERR_ISO, FLUX_MAX and SNR_ISO (SEXTRACTOR.md §3-4).
#pragma once

#include "octarc/measure/Measurement.h"

namespace octarc {

class IsophotalPhotometry final : public Measurement {
 public:
  std::string name() const override { return "IsophotalPhotometry"; }
  std::vector<OutputColumn> columns() const override;
  std::vector<std::string> dependencies() const override { return {"Footprint"}; }
  void measure(const Segment& segment, const MeasureContext& context,
               ObjectState& state) const override;
};

}  // namespace octarc
