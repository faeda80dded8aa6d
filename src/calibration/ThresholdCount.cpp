#include "octarc/calibration/ThresholdCount.h"

#include <cmath>
#include <set>

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
  for (const int n : s.levelCounts) {
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
    const int system = run.arcs.findColumn("SYSTEM");
    const int arcness = run.arcs.findColumn("ARCNESS");
    std::set<std::int64_t> found;
    for (std::int64_t r = 0; r < run.arcs.rows(); ++r) {
      if (run.arcs.value(r, arcness) > s.arcnessMin) {
        found.insert(std::int64_t(run.arcs.value(r, system)));
      }
    }
    row.withArcness = std::int64_t(found.size());
    row.fraction = double(row.withArcness) / double(row.systems);
    row.fractionSigma = std::sqrt(row.fraction * (1.0 - row.fraction) / double(row.systems));
    curve.rows.push_back(row);
  }
  if (!curve.rows.empty()) {
    const ThresholdCountRow& last = curve.rows.back();
    for (const ThresholdCountRow& r : curve.rows) {
      const double sigma = std::hypot(r.fractionSigma, last.fractionSigma);
      if (last.fraction - r.fraction <= sigma) {
        curve.flattensAtLevels = r.levels;
        break;
      }
    }
  }
  return curve;
}

}  // namespace octarc
