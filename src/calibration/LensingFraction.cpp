#include "octarc/calibration/LensingFraction.h"

#include <cmath>
#include <string>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

int requireColumn(const Table& t, const char* name) {
  const int c = t.findColumn(name);
  if (c < 0) {
    throw ConfigError(std::string("lensing fraction: the systems table has no column ") + name);
  }
  return c;
}

}  // namespace

LensingFractions lensingFractions(const Table& systems, const FractionCuts& cuts) {
  const int found = requireColumn(systems, "ARC_FOUND");
  const int arcness = requireColumn(systems, "ARCNESS");
  const int e = requireColumn(systems, "E_IMAGE");
  const int snr = requireColumn(systems, "SNR_ISO");
  LensingFractions out;
  out.cuts = cuts;
  out.simulatedSystems = systems.rows();
  const std::size_t bins = cuts.arcnessEdges.size() - 1;
  std::vector<std::int64_t> all(bins, 0), distorted(bins, 0);
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    if (systems.value(r, found) != 1.0) continue;
    ++out.arcSystems;
    const double a = systems.value(r, arcness);
    for (std::size_t k = 0; k < bins; ++k) {
      if (!(a >= cuts.arcnessEdges[k] && a < cuts.arcnessEdges[k + 1])) continue;
      ++all[k];
      if (systems.value(r, e) > cuts.ellipticityMin && systems.value(r, snr) > cuts.snrMin) {
        ++distorted[k];
      }
    }
  }
  const double n = double(out.arcSystems);
  for (std::size_t k = 0; k < bins; ++k) {
    for (const bool d : {false, true}) {
      FractionRow row;
      row.arcnessLo = cuts.arcnessEdges[k];
      row.arcnessHi = cuts.arcnessEdges[k + 1];
      row.distortedAndBright = d;
      row.systems = d ? distorted[k] : all[k];
      row.fraction = n > 0 ? double(row.systems) / n : 0.0;
      row.fractionSigma = n > 0 ? std::sqrt(row.fraction * (1.0 - row.fraction) / n) : 0.0;
      out.rows.push_back(row);
    }
  }
  return out;
}

}  // namespace octarc
