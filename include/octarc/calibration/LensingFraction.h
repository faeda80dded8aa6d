// The lensing-fraction table of METHOD.md section 3: of all strongly lensed simulated systems
// with an arc beyond the separation limit (ARC_FOUND = 1: an object >= 1" from the lens,
// resolved, at a level with the lens and the arc), the fraction whose chosen arc has arcness in
// 0.05-0.10, 0.10-0.15 and above 0.15, each also with e > 0.6 and S/N > 40 (significantly
// distorted and extended, bright enough for a reliable arcness).
//
// Uncertainty: binomial, sigma = sqrt(f (1 - f) / N) for a fraction f of N systems (0 when N is
// 0 or f is 0 or 1: then the count itself is the information).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

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
  std::int64_t systems = 0;
  double fraction = 0, fractionSigma = 0;
};

struct LensingFractions {
  FractionCuts cuts;
  std::int64_t simulatedSystems = 0;
  std::int64_t arcSystems = 0;    // the normalisation: ARC_FOUND = 1
  std::vector<FractionRow> rows;  // per arcness bin: all, then distorted and bright
};

// sqrt(f (1 - f) / n) for f = k / n; 0 for n <= 0.
double binomialSigma(std::int64_t k, std::int64_t n);

// From a simulate-lenses systems table (columns ARC_FOUND, ARCNESS, E_IMAGE, SNR_ISO).
// ConfigError naming the column when one is missing.
LensingFractions lensingFractions(const Table& systems, const FractionCuts& cuts = {});

}  // namespace octarc
