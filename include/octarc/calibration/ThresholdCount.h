// The fraction of simulated systems with a detected arc of arcness above 0.10 (at some level)
// against the number of detection thresholds between the same lowest and highest threshold
// (METHOD.md section 3): the systems are simulated again, with the same seed, for each number of
// levels, so the curve compares the same systems.
//
// Where it flattens: the smallest number of levels whose fraction is within one sigma of the
// fraction at the largest number tried, the sigma of the paired difference (the same systems):
// sqrt(n01 + n10) / N, n01 and n10 the systems found with one count and not the other. The
// counts are tried in increasing order, each once.
//
// The systems are those of the simulation only when it used the survey its header records and
// simulate lenses' defaults otherwise (population file, source database, magnitude and sigma_v
// ranges, lens light, stamp and ray tracing): the header does not record those.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/simulation/engine/LensSetup.h"

namespace octarc {

struct ThresholdCountSettings {
  std::vector<int> levelCounts = {1, 2, 3, 4, 5, 7, 10, 15, 20, 30};
  std::int64_t systems = 3000;
  std::uint64_t seed = 1;
  double arcnessMin = 0.10;
  std::string sourceDatabase;  // a RealGalaxyCatalog, or "" for the synthetic sources:
  int syntheticSources = 90;   // as simulate lenses makes them by default (--sources,
  double syntheticExtentHalfLightRadii = 4.0;  // --source-extent)
  int threads = 0;
};

struct ThresholdCountRow {
  int levels = 0;
  std::int64_t systems = 0;
  std::int64_t arcSystems = 0;   // with an arc (ARC_FOUND)
  std::int64_t withArcness = 0;  // with an arc row of ARCNESS above arcnessMin, at some level
  double fraction = 0, fractionSigma = 0;  // withArcness / systems, binomial
};

struct ThresholdCountCurve {
  std::vector<ThresholdCountRow> rows;
  int flattensAtLevels = 0;
};

// ConfigError for a level count below 1 or above 255, or no system.
ThresholdCountCurve thresholdCountCurve(const LensSetupOptions& survey,
                                        const ThresholdCountSettings& settings);

}  // namespace octarc
