// The S/N below which arcness becomes unreliable (METHOD.md section 3): simulated arcs, each
// scaled to arcness 0.10 at its highest S/N, remeasured at a series of background levels with
// many noise realisations each; the median and the 20 % / 80 % quantiles of the scaled arcness
// per S/N bin, and the floor.
//
// How, for each arc taken (a system of the simulation whose chosen arc has arcness in
// [arcnessMin, arcnessMax], the first `arcs` of them by SYSTEM):
//   1. the system is remade from its seed stream, without noise (its remade Einstein radius, lens
//      size and source position must match the simulation's: requireRemadeDraw);
//   2. for each noise factor f (the survey's sky sigma times f), `realisations` noise images
//      are added (Poisson on the sky, as simulate lenses), detected at one level and measured:
//      the chosen arc's isophote (its level's threshold, ADU) where the survey's lowest level
//      (t_min times the noise) reaches it, that lowest level otherwise (a survey sees a faint arc
//      no deeper). A fixed isophote keeps the arc the same object while the noise grows, which
//      the survey's own levels would not (they move with the noise, and an arc at another
//      isophote grows, shrinks or joins its lens). The arc is the object nearest the chosen
//      arc's centroid, within matchRadiusPix or its own SIZE_IMAGE and at the arc rules'
//      distance from the lens or more; otherwise it is lost in that realisation (counted);
//   3. its arcness a_0 at its highest S/N is the median over the realisations of the lowest
//      noise factor, and every measurement of that arc is scaled by referenceArcness / a_0.
// Each (arc, factor, realisation) draws from its own stream, so the result does not depend on
// the number of threads. Each measurement weighs its arc's SIM_WEIGHT (the population it stands
// for; 1 without the column): the medians and quantiles per bin are weighted
// (weightedSampleQuantiles, core/Statistics.h).
//
// The floor: a bin with at least minPerBin measurements is reliable when its median scaled
// arcness is within medianTolerance of referenceArcness and its 20 %-80 % spread is at most
// spreadMax (by default the width of one lensing-fraction bin, 0.05: below the floor an arc of
// arcness 0.10 is as likely measured in a neighbouring bin as in its own). The floor is the
// lower edge of the lowest bin of the run of reliable bins that reaches the highest S/N bin with
// enough measurements (bins with fewer are passed over).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <vector>

#include "octarc/calibration/SimulationOutput.h"
#include "octarc/core/Progress.h"

namespace octarc {

struct SnrFloorSettings {
  int arcs = 40;
  double arcnessMin = 0.05, arcnessMax = 0.20;  // chosen arcs taken
  // Factors of the survey's sky sigma: noiseFactorCount log-spaced from lo to hi.
  double noiseFactorLo = 0.25, noiseFactorHi = 8.0;
  int noiseFactorCount = 11;
  int realisations = 100;
  double referenceArcness = 0.10;
  // S/N bins: binCount log-spaced bins from snrLo to snrHi.
  double snrLo = 5.0, snrHi = 1280.0;
  int snrBinCount = 16;
  double medianTolerance = 0.01, spreadMax = 0.05;
  int minPerBin = 20;
  double matchRadiusPix = 3.0;
  std::uint64_t seed = 1;  // of the noise realisations
  int threads = 0;         // 0 = all cores
  ProgressFn progress;     // (arcs x factors done, arcs x factors), when given
};

struct SnrFloorBin {
  double snrLo = 0, snrHi = 0;
  std::int64_t measurements = 0;
  double median = 0, q20 = 0, q80 = 0;  // of the scaled arcness; NaN when empty
  bool reliable = false;
};

struct SnrFloorResult {
  std::vector<std::int64_t> systems;         // the arcs taken (SYSTEM)
  std::vector<double> referenceArcness;      // a_0 of each, unscaled
  std::vector<double> weights;               // SIM_WEIGHT of each
  double effectiveArcs = 0;                  // their Kish effective number
  double scaledToArcness = 0.10;             // settings.referenceArcness
  std::vector<double> noiseFactors;          // lowest first
  std::vector<std::int64_t> foundPerFactor;  // realisations in which the arc was found
  std::int64_t realisationsPerFactor = 0;    // arcs x realisations
  std::vector<SnrFloorBin> bins;
  std::int64_t measurements = 0;  // found, in any bin or not
  double floorSnr = 0.0;          // NaN when no bin is reliable
};

// The bins of (snr, scaled arcness) pairs and their statistics, each pair weighted by
// `weights` (empty: 1 each); pairs with a non-finite value or outside the bins are left out.
// Reliability as in the header comment.
std::vector<SnrFloorBin> snrFloorBins(const std::vector<double>& snr,
                                      const std::vector<double>& scaledArcness,
                                      const SnrFloorSettings& settings,
                                      const std::vector<double>& weights = {});
// The floor of already filled bins (header comment); NaN when the highest bin with enough
// measurements is not reliable.
double snrFloor(const std::vector<SnrFloorBin>& bins, int minPerBin);

// ConfigError for settings out of range (no arc, a factor range that is not increasing, more
// than 1000 noise factors or S/N bins, ...).
void checkSnrFloorSettings(const SnrFloorSettings& settings);

// The study on the arcs of `simulation`, remade with `survey` (resimulationOptions) and its
// `sources` (resimulationSources). ConfigError for combined outputs, when no chosen arc is in the
// arcness window, or when an arc taken cannot be remade (requireRemadeDraw on every arc taken).
SnrFloorResult snrFloorStudy(const SimulationOutput& simulation, const LensSetupOptions& survey,
                             const SourceDatabase& sources, const SnrFloorSettings& settings);

// The table of bins and the floor, as `octarc calibrate` prints them.
void printSnrFloor(std::ostream& out, const SnrFloorResult& result,
                   const SnrFloorSettings& settings);

}  // namespace octarc
