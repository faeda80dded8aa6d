#include "octarc/calibration/LensingFraction.h"

#include <cmath>
#include <string>

#include "octarc/core/Error.h"

namespace octarc {

LensingFractions lensingFractions(const Table& systems, const FractionCuts& cuts) {
  const int found = systems.requireColumn("ARC_FOUND", "lensing fraction");
  const int arcness = systems.requireColumn("ARCNESS", "lensing fraction");
  const int e = systems.requireColumn("E_IMAGE", "lensing fraction");
  const int snr = systems.requireColumn("SNR_ISO", "lensing fraction");
  const std::vector<double> weights = systemWeights(systems);
  LensingFractions out;
  out.cuts = cuts;
  out.simulatedSystems = systems.rows();
  const std::size_t bins = cuts.arcnessEdges.size() - 1;
  std::vector<WeightedCount> all(bins), distorted(bins);
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    if (systems.value(r, found) != 1.0) continue;
    const double w = weights[std::size_t(r)];
    out.arcSystems.add(w);
    const double a = systems.value(r, arcness);
    for (std::size_t k = 0; k < bins; ++k) {
      if (!(a >= cuts.arcnessEdges[k] && a < cuts.arcnessEdges[k + 1])) continue;
      all[k].add(w);
      if (systems.value(r, e) > cuts.ellipticityMin && systems.value(r, snr) > cuts.snrMin) {
        distorted[k].add(w);
      }
    }
  }
  const double total = out.arcSystems.weightSum, effective = out.arcSystems.effective();
  for (std::size_t k = 0; k < bins; ++k) {
    for (const bool d : {false, true}) {
      const WeightedCount& in = d ? distorted[k] : all[k];
      FractionRow row;
      row.arcnessLo = cuts.arcnessEdges[k];
      row.arcnessHi = cuts.arcnessEdges[k + 1];
      row.distortedAndBright = d;
      row.systems = in.count;
      row.weight = in.weightSum;
      row.fraction = weightedFractionInterval(total > 0 ? in.weightSum / total : 0.0, effective);
      out.rows.push_back(row);
    }
  }
  return out;
}

}  // namespace octarc
