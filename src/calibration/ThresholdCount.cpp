#include "octarc/calibration/ThresholdCount.h"

#include <algorithm>
#include <cmath>

#include "octarc/calibration/LensingFraction.h"
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
  parallelForDynamic(
      s.systems, resolveThreads(s.threads),
      [&](std::int64_t i) {
        const RenderedSystem rendered = renderSystem(setups.front(), sources, s.seed, i);
        if (!rendered.draw.rendered) return;
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
  ThresholdCountCurve curve;
  for (std::size_t c = 0; c < counts.size(); ++c) {
    ThresholdCountRow row;
    row.levels = counts[c];
    row.systems = s.systems;
    row.arcSystems = std::count(flagged(arcFound, c), flagged(arcFound, c + 1), 1);
    row.withArcness = std::count(flagged(withArcness, c), flagged(withArcness, c + 1), 1);
    row.fraction = double(row.withArcness) / double(row.systems);
    row.fractionSigma = binomialSigma(row.withArcness, row.systems);
    curve.rows.push_back(row);
  }
  // Flat from the fewest levels whose fraction is within one sigma of the most levels' fraction,
  // the sigma of a paired difference (the same systems): sqrt(n01 + n10) / N, n01 and n10 the
  // systems found with one number of levels and not the other.
  const std::size_t most = counts.size() - 1;
  for (std::size_t c = 0; c < counts.size(); ++c) {
    std::int64_t onlyMost = 0, onlyThis = 0;
    for (std::size_t i = 0; i < systems; ++i) {
      const bool inMost = withArcness[most * systems + i], inThis = withArcness[c * systems + i];
      onlyMost += inMost && !inThis;
      onlyThis += inThis && !inMost;
    }
    const double n = double(s.systems);
    if (double(onlyMost - onlyThis) / n <= std::sqrt(double(onlyMost + onlyThis)) / n) {
      curve.flattensAtLevels = counts[c];
      break;
    }
  }
  return curve;
}

}  // namespace octarc
