// The lensing-fraction table of METHOD.md section 3: of all strongly lensed simulated systems
// with an arc beyond the separation limit (ARC_FOUND = 1: an object >= 1" from the lens,
// resolved, at a level with the lens and the arc), the fraction whose chosen arc has arcness in
// 0.05-0.10, 0.10-0.15 and above 0.15, each also with e > 0.6 and S/N > 40 (significantly
// distorted and extended, bright enough for a reliable arcness).
//
// Weighted (calibration/Weights.h): a fraction is the SIM_WEIGHT sum of the systems in the bin
// over the SIM_WEIGHT sum of the systems with an arc, with its Clopper-Pearson 68.27 % interval
// (n the Kish effective number of the systems with an arc, k = f n): 0 of N has an upper bound
// above 0.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "octarc/calibration/Weights.h"
#include "octarc/core/Table.h"

namespace octarc {

struct FractionCuts {
  std::vector<double> arcnessEdges = {0.05, 0.10, 0.15, std::numeric_limits<double>::infinity()};
  double ellipticityMin = 0.6;  // E_IMAGE >
  double snrMin = 40.0;         // SNR_ISO >
};

struct FractionRow {
  double arcnessLo = 0, arcnessHi = 0;  // lo <= ARCNESS < hi
  bool distortedAndBright = false;      // also E_IMAGE > ellipticityMin and SNR_ISO > snrMin
  std::int64_t systems = 0;             // rows in the bin
  double weight = 0;                    // their SIM_WEIGHT sum
  FractionInterval fraction;
};

struct LensingFractions {
  FractionCuts cuts;
  std::int64_t simulatedSystems = 0;  // rows of the table (calibrate: systems drawn, OCTNSYS)
  WeightedCount arcSystems;           // the normalisation: ARC_FOUND = 1
  std::vector<FractionRow> rows;      // per arcness bin: all, then distorted and bright
};

// From a simulate-lenses systems table (columns ARC_FOUND, ARCNESS, E_IMAGE, SNR_ISO; SIM_WEIGHT
// when there, else every row weighs 1). ConfigError naming the column when one is missing.
LensingFractions lensingFractions(const Table& systems, const FractionCuts& cuts = {});

}  // namespace octarc
