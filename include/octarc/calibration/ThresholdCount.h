// The fraction of simulated systems with a detected arc of arcness above 0.10 (at some level)
// against the number of detection thresholds between the same lowest and highest threshold
// (METHOD.md section 3): the systems are simulated again with the same seed, each rendered once
// (its stamp, noise included, does not depend on the levels) and detected with each number of
// levels, so the curve compares the same systems at the cost of one rendering each.
//
// Where it flattens: the smallest number of levels whose fraction is within one sigma of the
// fraction at the largest number tried, the sigma of the paired difference (the same systems):
// sqrt(sum of w^2 over the discordant systems) / N, the discordant systems those found with one
// count and not the other (sqrt(n01 + n10) / N with unit weights). The counts are tried in
// increasing order, each once.
//
// The systems are those of the simulation when it is remade with its own options
// (resimulationOptions, resimulationSources; calibrate checks that with checkRemade), sampled as
// it sampled them: with importance sampling only some of the N systems drawn are rendered, each
// with its weight 1 / (render probability), and a system not rendered contributes nothing. The
// fraction is the weight sum of the systems found over N; its Clopper-Pearson interval takes the
// Kish effective number of the rendered systems and of those skipped below the skip limit
// (weight 1 each: they give no arc) as the trials (calibration/Weights.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/calibration/SimulationOutput.h"
#include "octarc/calibration/Weights.h"
#include "octarc/core/Progress.h"

namespace octarc {

struct ThresholdCountSettings {
  std::vector<int> levelCounts = {1, 2, 3, 4, 5, 7, 10, 15, 20, 30};
  std::int64_t systems = 3000;
  std::uint64_t seed = 1;
  double arcnessMin = 0.10;
  ProgressFn progress;  // (systems done, systems), when given
  int threads = 0;
};

struct ThresholdCountRow {
  int levels = 0;
  std::int64_t systems = 0;     // drawn
  std::int64_t rendered = 0;    // of them rendered
  std::int64_t arcSystems = 0;  // rendered with an arc (ARC_FOUND)
  WeightedCount withArcness;    // with an arc row of ARCNESS above arcnessMin, at some level
  FractionInterval fraction;    // withArcness weight / systems
};

struct ThresholdCountCurve {
  std::vector<ThresholdCountRow> rows;
  int flattensAtLevels = 0;
};

// ConfigError for a level count below 1 or above 255, or no system.
ThresholdCountCurve thresholdCountCurve(const LensSetupOptions& survey,
                                        const SourceDatabase& sources,
                                        const ThresholdCountSettings& settings);

}  // namespace octarc
