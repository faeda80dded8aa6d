#include "octarc/calibration/ThresholdCount.h"

#include <algorithm>
#include <cmath>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

ThresholdCountCurve thresholdCountCurve(const LensSetupOptions& survey,
                                        const SourceDatabase& sources,
                                        const ThresholdCountSettings& s) {
  if (s.systems < 1) throw ConfigError("THRESHOLD_SYSTEMS: must be at least 1");
  std::vector<int> counts = s.levelCounts;
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  if (counts.empty()) throw ConfigError("THRESHOLD_NLEVELS: give at least one number of levels");
  std::vector<SimulationSetup> setups;
  for (const int n : counts) {
    if (n < 1 || n > 255) throw ConfigError("THRESHOLD_NLEVELS: every count must be in 1..255");
    LensSetupOptions o = survey;
    o.detectLevelCount = n;
    setups.push_back(makeSimulationSetup(o));
  }
  // Each system is rendered once (its stamp does not depend on the levels) and detected with
  // every number of levels; flags per (count, system).
  const std::size_t systems = std::size_t(s.systems);
  std::vector<char> arcFound(counts.size() * systems, 0), withArcness(arcFound.size(), 0);
  // Per system: its weight (0 when not rendered) and whether it was skipped below the limit.
  std::vector<double> weight(systems, 0.0);
  std::vector<char> skipped(systems, 0);
  parallelForDynamic(
      s.systems, resolveThreads(s.threads),
      [&](std::int64_t i) {
        const RenderedSystem rendered = renderSystem(setups.front(), sources, s.seed, i);
        skipped[std::size_t(i)] = rendered.draw.skipped;
        if (!rendered.draw.rendered) return;
        weight[std::size_t(i)] = rendered.draw.weight();
        for (std::size_t c = 0; c < counts.size(); ++c) {
          std::mt19937_64 rng = rendered.rng;  // the arc-level choice, as simulate lenses makes it
          const DetectedSystem d = detectSystem(rendered.image, setups[c], rng);
          const std::size_t k = c * systems + std::size_t(i);
          arcFound[k] = d.arcs.chosenRow >= 0;
          const int arcness = d.objects.requireColumn("ARCNESS", "threshold count");
          for (std::int64_t row : d.arcs.arcRows) {
            if (d.objects.value(row, arcness) > s.arcnessMin) withArcness[k] = 1;
          }
        }
      },
      [&](std::int64_t done) {
        if (s.progress) s.progress(done, s.systems);
      });
  // Flags of count c for system i at c * systems + i.
  auto flagged = [&](const std::vector<char>& flags, std::size_t c) {
    return flags.begin() + std::ptrdiff_t(c * systems);
  };
  // The trials of the intervals: the rendered systems (their weights) and those skipped below
  // the skip limit (known to give no arc: weight 1).
  WeightedCount known;
  std::int64_t rendered = 0;
  for (std::size_t i = 0; i < systems; ++i) {
    if (weight[i] > 0.0) {
      known.add(weight[i]);
      ++rendered;
    } else if (skipped[i]) {
      known.add(1.0);
    }
  }
  const double n = double(s.systems);
  ThresholdCountCurve curve;
  for (std::size_t c = 0; c < counts.size(); ++c) {
    ThresholdCountRow row;
    row.levels = counts[c];
    row.systems = s.systems;
    row.rendered = rendered;
    row.arcSystems = std::count(flagged(arcFound, c), flagged(arcFound, c + 1), 1);
    for (std::size_t i = 0; i < systems; ++i) {
      if (withArcness[c * systems + i]) row.withArcness.add(weight[i]);
    }
    row.fraction = weightedFractionInterval(row.withArcness.weightSum / n, known.effective());
    curve.rows.push_back(row);
  }
  // Flat from the fewest levels whose fraction is within one sigma of the most levels' fraction,
  // the sigma of a paired difference (the same systems): sqrt(sum of w^2 of the discordant
  // systems) / N, those found with one number of levels and not the other.
  const std::size_t most = counts.size() - 1;
  for (std::size_t c = 0; c < counts.size(); ++c) {
    double onlyMost = 0, onlyThis = 0, discordantSquares = 0;
    for (std::size_t i = 0; i < systems; ++i) {
      const bool inMost = withArcness[most * systems + i], inThis = withArcness[c * systems + i];
      if (inMost == inThis) continue;
      (inMost ? onlyMost : onlyThis) += weight[i];
      discordantSquares += weight[i] * weight[i];
    }
    if ((onlyMost - onlyThis) / n <= std::sqrt(discordantSquares) / n) {
      curve.flattensAtLevels = counts[c];
      break;
    }
  }
  return curve;
}

}  // namespace octarc
