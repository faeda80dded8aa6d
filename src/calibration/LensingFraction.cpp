#include "octarc/calibration/LensingFraction.h"

#include <cmath>
#include <string>

#include "octarc/core/Error.h"

namespace octarc {

double binomialSigma(std::int64_t k, std::int64_t n) {
  if (n <= 0) return 0.0;
  const double f = double(k) / double(n);
  return std::sqrt(f * (1.0 - f) / double(n));
}

LensingFractions lensingFractions(const Table& systems, const FractionCuts& cuts) {
  const int found = systems.requireColumn("ARC_FOUND", "lensing fraction");
  const int arcness = systems.requireColumn("ARCNESS", "lensing fraction");
  const int e = systems.requireColumn("E_IMAGE", "lensing fraction");
  const int snr = systems.requireColumn("SNR_ISO", "lensing fraction");
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
      row.fractionSigma = binomialSigma(row.systems, out.arcSystems);
      out.rows.push_back(row);
    }
  }
  return out;
}

}  // namespace octarc
