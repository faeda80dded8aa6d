#include "octarc/calibration/SnrFloor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "octarc/calibration/Weights.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Statistics.h"
#include "octarc/run/Levels.h"
#include "octarc/simulation/Noise.h"
#include "octarc/simulation/Seeds.h"

namespace octarc {

namespace {

// One arc taken: its system, the isophote (ADU) and centroid (0-based pixels) of its chosen row.
struct ArcTarget {
  std::int64_t system = 0;
  double weight = 1.0;  // SIM_WEIGHT
  double isophoteAdu = 0;
  double xPix = 0, yPix = 0;
  ImageF noiseFree;  // single precision, as simulate lenses hands its stamps to the detector
};

// The arc's measurement in one noise realisation, detected at the one level of `setup`: ARCNESS
// and SNR_ISO of the object nearest its centroid, within the match radius or the object's own
// size (SIZE_IMAGE: at a higher isophote a faint arc shrinks and its centroid moves), and as far
// from the lens as the arc rules ask; NaN when there is none.
struct Measured {
  double arcness = std::nan(""), snr = std::nan("");
};

Measured measureOnce(const ArcTarget& arc, const SimulationSetup& setup, double matchRadiusPix,
                     std::mt19937_64& rng) {
  ImageD noisy(arc.noiseFree.width(), arc.noiseFree.height());
  for (std::int64_t i = 0; i < noisy.size(); ++i) noisy[i] = arc.noiseFree[i];
  simulation::addPoissonSkyNoise(noisy, setup.observing.skySigmaAdu,
                                 setup.observing.gainElectronsPerAdu, rng);
  ImageF pixels(noisy.width(), noisy.height());
  for (std::int64_t i = 0; i < pixels.size(); ++i) pixels[i] = float(noisy[i]);
  PreparedImage prepared = prepareStamp(std::move(pixels), setup);
  const Table objects = detectAndMeasure(prepared, setup, nullptr);
  const int level = objects.requireColumn("THRESH_LEVEL", "S/N floor");
  const int x = objects.requireColumn("X_IMAGE", "S/N floor");
  const int y = objects.requireColumn("Y_IMAGE", "S/N floor");
  const int arcness = objects.requireColumn("ARCNESS", "S/N floor");
  const int snr = objects.requireColumn("SNR_ISO", "S/N floor");
  const int size = objects.requireColumn("SIZE_IMAGE", "S/N floor");
  const simulation::SurveyGrid& grid = setup.observing.grid;
  Measured best;
  double bestDistance = INFINITY;
  for (std::int64_t r = 0; r < objects.rows(); ++r) {
    if (int(objects.value(r, level)) != 1) continue;
    // X_IMAGE/Y_IMAGE are 1-based.
    const double d =
        std::hypot(objects.value(r, x) - 1.0 - arc.xPix, objects.value(r, y) - 1.0 - arc.yPix);
    // Never the lens (a large object whose size would reach the arc): the arc rule's distance.
    const double fromLensArcsec =
        grid.pixelScaleArcsec * std::hypot(objects.value(r, x) - 1.0 - grid.lensXPix,
                                           objects.value(r, y) - 1.0 - grid.lensYPix);
    if (fromLensArcsec < setup.arcRules.minDistanceArcsec) continue;
    if (d <= std::max(matchRadiusPix, objects.value(r, size)) && d < bestDistance) {
      bestDistance = d;
      best = {objects.value(r, arcness), objects.value(r, snr)};
    }
  }
  return best;
}

}  // namespace

void checkSnrFloorSettings(const SnrFloorSettings& s) {
  if (s.arcs < 1) throw ConfigError("SNR_ARCS: must be at least 1");
  if (!(s.arcnessMax > s.arcnessMin)) throw ConfigError("SNR_ARCNESS: the range is empty");
  if (!(s.noiseFactorLo > 0) || !(s.noiseFactorHi > s.noiseFactorLo) || s.noiseFactorCount < 2) {
    throw ConfigError("SNR_NOISE: need 0 < lowest < highest factor and at least 2 factors");
  }
  if (s.realisations < 1) throw ConfigError("SNR_REALISATIONS: must be at least 1");
  if (!(s.snrLo > 0) || !(s.snrHi > s.snrLo) || s.snrBinCount < 1) {
    throw ConfigError("SNR_BINS: need 0 < lowest < highest S/N and at least 1 bin");
  }
  if (!(s.referenceArcness > 0)) throw ConfigError("S/N floor: the reference arcness must be > 0");
  if (!(s.matchRadiusPix > 0)) throw ConfigError("S/N floor: the match radius must be > 0");
  if (s.noiseFactorCount > 1000) throw ConfigError("SNR_NOISE: at most 1000 noise factors");
  if (s.snrBinCount > 1000) throw ConfigError("SNR_BINS: at most 1000 bins");
  if (std::int64_t(s.arcs) * s.noiseFactorCount * s.realisations > 100000000) {
    throw ConfigError("SNR_ARCS x SNR_NOISE factors x SNR_REALISATIONS: at most 10^8 images");
  }
}

std::vector<SnrFloorBin> snrFloorBins(const std::vector<double>& snr,
                                      const std::vector<double>& scaled, const SnrFloorSettings& s,
                                      const std::vector<double>& weights) {
  const std::vector<double> edges = logSpacedLevels(s.snrLo, s.snrHi, s.snrBinCount + 1);
  std::vector<std::vector<double>> values(std::size_t(s.snrBinCount)), binWeights(values.size());
  for (std::size_t i = 0; i < snr.size() && i < scaled.size(); ++i) {
    if (!std::isfinite(snr[i]) || !std::isfinite(scaled[i])) continue;
    if (snr[i] < edges.front() || snr[i] >= edges.back()) continue;
    const auto k =
        std::size_t(std::upper_bound(edges.begin(), edges.end(), snr[i]) - edges.begin() - 1);
    values[k].push_back(scaled[i]);
    binWeights[k].push_back(weights.empty() ? 1.0 : weights[i]);
  }
  std::vector<SnrFloorBin> bins;
  for (std::size_t k = 0; k < values.size(); ++k) {
    SnrFloorBin b;
    b.snrLo = edges[k];
    b.snrHi = edges[k + 1];
    b.measurements = std::int64_t(values[k].size());
    const std::vector<double> q =
        weightedSampleQuantiles(values[k], binWeights[k], {0.2, 0.5, 0.8});
    b.q20 = q[0];
    b.median = q[1];
    b.q80 = q[2];
    b.reliable = b.measurements >= s.minPerBin &&
                 std::abs(b.median - s.referenceArcness) <= s.medianTolerance &&
                 b.q80 - b.q20 <= s.spreadMax;
    bins.push_back(b);
  }
  return bins;
}

double snrFloor(const std::vector<SnrFloorBin>& bins, int minPerBin) {
  double floor = std::nan("");
  for (auto b = bins.rbegin(); b != bins.rend(); ++b) {
    if (b->measurements < minPerBin) continue;  // too few to say: passed over
    if (!b->reliable) break;
    floor = b->snrLo;
  }
  return floor;
}

SnrFloorResult snrFloorStudy(const SimulationOutput& sim, const LensSetupOptions& survey,
                             const SourceDatabase& sources, const SnrFloorSettings& s) {
  checkSnrFloorSettings(s);
  if (sim.outputs > 1) {
    // SYSTEM restarts at 0 in each output, and each has its own seed.
    throw ConfigError(sim.path + ": SNR_STUDY takes one simulation output, not several");
  }
  const Table& systems = sim.systems;
  const int cSystem = systems.requireColumn("SYSTEM", sim.path);
  const int cFound = systems.requireColumn("ARC_FOUND", sim.path);
  const int cArcness = systems.requireColumn("ARCNESS", sim.path);
  const int cLevel = systems.requireColumn("THRESH_LEVEL", sim.path);
  const int cX = systems.requireColumn("X_IMAGE", sim.path);
  const int cY = systems.requireColumn("Y_IMAGE", sim.path);
  const std::vector<double> rowWeights = systemWeights(systems);
  std::vector<std::pair<std::int64_t, std::int64_t>> taken;  // (SYSTEM, row)
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    const double a = systems.value(r, cArcness);
    if (systems.value(r, cFound) == 1.0 && a >= s.arcnessMin && a <= s.arcnessMax) {
      taken.emplace_back(std::int64_t(systems.value(r, cSystem)), r);
    }
  }
  if (taken.empty()) {
    throw ConfigError(sim.path + ": no chosen arc with ARCNESS in [" +
                      std::to_string(s.arcnessMin) + ", " + std::to_string(s.arcnessMax) +
                      "] for the S/N floor study");
  }
  std::sort(taken.begin(), taken.end());
  if (taken.size() > std::size_t(s.arcs)) taken.resize(std::size_t(s.arcs));
  const SimulationSetup base = makeSimulationSetup(survey);
  const int threads = resolveThreads(s.threads);

  // 1. The noise-free stamps; every arc taken must be remade as the simulation made it.
  std::vector<ArcTarget> arcs(taken.size());
  SimulationSetup noiseFree = base;
  noiseFree.observing.addNoise = false;
  parallelForDynamic(std::int64_t(arcs.size()), threads, [&](std::int64_t i) {
    ArcTarget& arc = arcs[std::size_t(i)];
    const std::int64_t row = taken[std::size_t(i)].second;
    arc.system = taken[std::size_t(i)].first;
    arc.weight = rowWeights[std::size_t(row)];
    const int level = int(systems.value(row, cLevel));
    if (level < 1 || std::size_t(level) > base.thresholdsAdu.size()) {
      throw ConfigError(sim.path + ": system " + std::to_string(arc.system) +
                        " has its arc at a level the survey setup does not have");
    }
    arc.isophoteAdu = base.thresholdsAdu[std::size_t(level) - 1];
    arc.xPix = systems.value(row, cX) - 1.0;
    arc.yPix = systems.value(row, cY) - 1.0;
    RenderedSystem rendered = renderSystem(noiseFree, sources, sim.setup.seed, arc.system);
    requireRemadeDraw(sim, row, rendered.draw);
    arc.noiseFree = std::move(rendered.image);
  });

  // 2. Every (arc, factor, realisation), each from its own stream.
  SnrFloorResult out;
  out.scaledToArcness = s.referenceArcness;
  out.noiseFactors = logSpacedLevels(s.noiseFactorLo, s.noiseFactorHi, s.noiseFactorCount);
  const std::size_t factors = out.noiseFactors.size(), runs = std::size_t(s.realisations);
  std::vector<Measured> measured(arcs.size() * factors * runs);
  parallelForDynamic(
      std::int64_t(arcs.size() * factors), threads,
      [&](std::int64_t task) {
        const std::size_t a = std::size_t(task) / factors, f = std::size_t(task) % factors;
        // One level: the arc's own isophote where the survey's lowest level reaches it, the lowest
        // level (t_min times the noise) otherwise.
        SimulationSetup setup = base;
        setup.observing.skySigmaAdu *= out.noiseFactors[f];
        setup.thresholdsAdu = {
            std::max(arcs[a].isophoteAdu, base.thresholdsAdu.front() * out.noiseFactors[f])};
        for (std::size_t r = 0; r < runs; ++r) {
          const std::size_t k = (a * factors + f) * runs + r;
          std::mt19937_64 rng = simulation::systemRng(s.seed, std::uint64_t(k));
          measured[k] = measureOnce(arcs[a], setup, s.matchRadiusPix, rng);
        }
      },
      [&](std::int64_t done) {
        if (s.progress) s.progress(done, std::int64_t(arcs.size() * factors));
      });

  // 3. Scaled to the reference arcness at each arc's highest S/N (the lowest noise factor).
  out.foundPerFactor.assign(factors, 0);
  out.realisationsPerFactor = std::int64_t(arcs.size() * runs);
  std::vector<double> snr, scaled, weight;
  WeightedCount takenArcs;
  for (std::size_t a = 0; a < arcs.size(); ++a) {
    std::vector<double> lowest;
    for (std::size_t r = 0; r < runs; ++r)
      lowest.push_back(measured[a * factors * runs + r].arcness);
    const double a0 = sampleMedian(lowest);
    out.systems.push_back(arcs[a].system);
    out.referenceArcness.push_back(a0);
    out.weights.push_back(arcs[a].weight);
    takenArcs.add(arcs[a].weight);
    for (std::size_t f = 0; f < factors; ++f) {
      for (std::size_t r = 0; r < runs; ++r) {
        const Measured& m = measured[(a * factors + f) * runs + r];
        if (!std::isfinite(m.arcness)) continue;
        ++out.foundPerFactor[f];
        if (!(a0 > 0)) continue;  // lost at its highest S/N: nothing to scale to
        ++out.measurements;
        snr.push_back(m.snr);
        scaled.push_back(m.arcness * s.referenceArcness / a0);
        weight.push_back(arcs[a].weight);
      }
    }
  }
  out.effectiveArcs = takenArcs.effective();
  out.bins = snrFloorBins(snr, scaled, s, weight);
  out.floorSnr = snrFloor(out.bins, s.minPerBin);
  return out;
}

void printSnrFloor(std::ostream& out, const SnrFloorResult& r, const SnrFloorSettings& s) {
  char line[200];
  std::snprintf(line, sizeof line,
                "S/N floor (%s scaled to ARCNESS %.2f, %d noise realisations per noise "
                "factor):\n      S/N        n    median   20%%     80%%\n",
                countWithEffective(std::int64_t(r.systems.size()), r.effectiveArcs).c_str(),
                s.referenceArcness, s.realisations);
  out << line;
  for (const SnrFloorBin& b : r.bins) {
    if (b.measurements == 0) continue;
    std::snprintf(line, sizeof line, "  %6.1f-%-6.1f %6lld  %.4f  %.4f  %.4f%s\n", b.snrLo, b.snrHi,
                  static_cast<long long>(b.measurements), b.median, b.q20, b.q80,
                  b.reliable ? "" : "  unreliable");
    out << line;
  }
  std::snprintf(line, sizeof line,
                "  arcness unreliable below S/N %s (median within %g of %.2f, 20-80%% within "
                "%g)\n",
                formatNumber(r.floorSnr, "%.1f", true).c_str(), s.medianTolerance,
                s.referenceArcness, s.spreadMax);
  out << line;
}

}  // namespace octarc
