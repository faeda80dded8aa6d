#include "octarc/calibration/ThresholdCount.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "octarc/calibration/LensingFraction.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/simulation/engine/LensCatalog.h"

namespace octarc {

ThresholdCountCurve thresholdCountCurve(const LensSetupOptions& survey,
                                        const ThresholdCountSettings& s) {
  if (s.systems < 1) throw ConfigError("THRESHOLD_SYSTEMS: must be at least 1");
  simulation::SyntheticGalaxyOptions galaxy;
  galaxy.stampHalfLightRadii = s.syntheticExtentHalfLightRadii;
  // The synthetic sources of simulate lenses: their own seed stream, whatever the master seed.
  const SourceDatabase sources =
      s.sourceDatabase.empty()
          ? SourceDatabase::synthetic(s.syntheticSources, kSyntheticSourceSeed, galaxy)
          : SourceDatabase::fromRealGalaxyCatalog(s.sourceDatabase);
  ThresholdCountCurve curve;
  std::vector<int> counts = s.levelCounts;
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  std::vector<std::set<std::int64_t>> found(counts.size());  // per count: systems with an arc
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const int n = counts[i];
    if (n < 1 || n > 255) throw ConfigError("THRESHOLD_NLEVELS: every count must be in 1..255");
    LensSetupOptions o = survey;
    o.detectLevelCount = n;
    const SimulationSetup setup = makeSimulationSetup(o);
    const LensRun run =
        runLensSimulation(setup, sources, s.seed, s.systems, resolveThreads(s.threads), 0, {});
    ThresholdCountRow row;
    row.levels = n;
    row.systems = run.systems.rows();
    row.arcSystems = run.systemsWithArc;
    const int system = run.arcs.requireColumn("SYSTEM", "threshold count");
    const int arcness = run.arcs.requireColumn("ARCNESS", "threshold count");
    for (std::int64_t r = 0; r < run.arcs.rows(); ++r) {
      if (run.arcs.value(r, arcness) > s.arcnessMin) {
        found[i].insert(std::int64_t(run.arcs.value(r, system)));
      }
    }
    row.withArcness = std::int64_t(found[i].size());
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
