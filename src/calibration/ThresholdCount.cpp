#include "octarc/calibration/ThresholdCount.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "octarc/calibration/LensingFraction.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

ThresholdCountCurve thresholdCountCurve(const LensSetupOptions& survey,
                                        const ThresholdCountSettings& s) {
  if (s.systems < 1) throw ConfigError("THRESHOLD_SYSTEMS: must be at least 1");
  std::vector<int> counts = s.levelCounts;
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  std::vector<SimulationSetup> setups;
  for (const int n : counts) {
    if (n < 1 || n > 255) throw ConfigError("THRESHOLD_NLEVELS: every count must be in 1..255");
    LensSetupOptions o = survey;
    o.detectLevelCount = n;
    setups.push_back(makeSimulationSetup(o));
  }
  const SourceDatabase sources = s.sources.make();
  // Each system is rendered once (its stamp does not depend on the levels) and detected with
  // every number of levels; flags per (count, system).
  const std::size_t systems = std::size_t(s.systems);
  std::vector<char> arcFound(counts.size() * systems, 0), withArcness(arcFound.size(), 0);
  parallelForDynamic(
      s.systems, resolveThreads(s.threads),
      [&](std::int64_t i) {
        const RenderedSystem rendered = renderSystem(setups.front(), sources, s.seed, i);
        if (rendered.draw.skipped) return;
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
  ThresholdCountCurve curve;
  std::vector<std::set<std::int64_t>> found(counts.size());  // per count: systems with an arc
  for (std::size_t c = 0; c < counts.size(); ++c) {
    ThresholdCountRow row;
    row.levels = counts[c];
    row.systems = s.systems;
    for (std::size_t i = 0; i < systems; ++i) {
      row.arcSystems += arcFound[c * systems + i];
      if (withArcness[c * systems + i]) found[c].insert(std::int64_t(i));
    }
    row.withArcness = std::int64_t(found[c].size());
    row.fraction = double(row.withArcness) / double(row.systems);
    row.fractionSigma = binomialSigma(row.withArcness, row.systems);
    curve.rows.push_back(row);
  }
  // Flat from the fewest levels whose fraction is within one sigma of the most levels' fraction,
  // the sigma of a paired difference (the same systems): sqrt(n01 + n10) / N, n01 and n10 the
  // systems found with one number of levels and not the other.
  if (!curve.rows.empty()) {
    const std::set<std::int64_t>& most = found.back();
    for (std::size_t i = 0; i < curve.rows.size(); ++i) {
      std::int64_t onlyMost = 0, onlyThis = 0;
      for (std::int64_t id : most) onlyMost += found[i].count(id) ? 0 : 1;
      for (std::int64_t id : found[i]) onlyThis += most.count(id) ? 0 : 1;
      const double n = double(curve.rows[i].systems);
      const double difference = double(onlyMost - onlyThis) / n;
      if (difference <= std::sqrt(double(onlyMost + onlyThis)) / n) {
        curve.flattensAtLevels = curve.rows[i].levels;
        break;
      }
    }
  }
  return curve;
}

}  // namespace octarc
