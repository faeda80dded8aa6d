// `octarc simulate lenses` as a library: N systems simulated in parallel (LensSimulation.h),
// gathered into the systems table (truth + the chosen arc) and the arc table (every arc row at
// every qualifying level), and written as one FITS-LDAC file.
//
// Each system is reproducible from (seed, index) alone and its results are placed by index, so
// the tables do not depend on the thread count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/core/Image.h"
#include "octarc/core/Progress.h"
#include "octarc/core/Table.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

// The columns of the systems table: truth, SIM_WEIGHT, ARC_FOUND, LENS_DISTANCE, then the chosen
// arc's measuredColumns() (NaN without an arc). With a second band `band` (non-empty), then the
// injected colours SOURCE_COLOUR_TRUE_<band> and LENS_COLOUR_TRUE_<band>, and the band's
// measured columns of the chosen arc and the lens (secondBandColumns).
std::vector<ColumnSpec> lensSystemColumns(const std::string& band = "");
// The columns of the arc table: SYSTEM, CHOSEN, LENS_DISTANCE, then measuredColumns(), then
// with a second band its measured columns of the row and of its lens.
std::vector<ColumnSpec> lensArcColumns(const std::string& band = "");
// The measured columns of second band B, with the names and meaning of the search's candidate
// columns (so that one expression, e.g. ARC_COLOUR_B - LENS_COLOUR_B, works on both): MAG_B,
// MAGERR_B (the arc row's isophotal magnitude in B, in its footprint), LENS_MAG_B, LENS_MAGERR_B
// (the lens's, in its footprint at level 1, or at the row's level when it joins the arc at level
// 1: SecondBandMagnitudes; NaN when it is not detected apart from the arc),
// ARC_COLOUR_B, ARC_COLOURERR_B, LENS_COLOUR_B, LENS_COLOURERR_B (B minus the measurement band,
// both isophotal in the same footprint).
std::vector<ColumnSpec> secondBandColumns(const std::string& band);

struct LensRun {
  Table systems;           // lensSystemColumns(), one row per rendered system, in index order
  Table arcs;              // lensArcColumns()
  std::int64_t drawn = 0;  // systems drawn from the population (the run's count)
  std::int64_t systemsWithArc = 0;  // rendered systems with an arc
  std::int64_t redraws = 0;         // lens-source pairs redrawn (LensSystemDraw::redraws)
  std::int64_t rejections = 0;      // draws the sampler turned down (LensSystemDraw::rejections)
  std::int64_t skipped = 0;         // systems below the skip limit (LensSystemDraw::skipped)
  std::int64_t rendered = 0;        // rows of `systems`
  // Of SIM_WEIGHT over the rendered systems, and of it and its square over those with an arc,
  // summed in row order (sumWeights) so that they do not depend on threads or ranks.
  double weightSum = 0;
  double arcWeightSum = 0, arcWeightSquaredSum = 0;
  void sumWeights();
  // Kish's effective number of arcs, (sum w)^2 / sum w^2 over the systems with an arc: the
  // number of plainly drawn arcs that would give estimates as precise.
  double effectiveArcs() const;
  StageTimings timings;        // summed over systems
  std::vector<ImageF> stamps;  // the first `stampCount` systems' stamps
};

// Simulates systems firstIndex..firstIndex+count-1 of `seed` on `threads` threads (the stamps
// kept are those of the first `stampCount` of them); `progress` gets the number done.
LensRun runLensSimulation(const SimulationSetup& setup, const SourceDatabase& sources,
                          std::uint64_t seed, std::int64_t count, int threads, int stampCount,
                          const ProgressFn& progress, std::int64_t firstIndex = 0);

// The OCT* header cards of the systems file: seed, counts, survey, levels, source database, and
// with a second band OCTBAND (its name) and its colours OCTSCOLM, OCTSCOLS (source mean and
// scatter), OCTLCOLM, OCTLCOLS (lens).
std::vector<std::string> lensRunCards(const LensRun& run, const SimulationSetup& setup,
                                      const SourceDatabase& sources, std::uint64_t seed);

// Writes the two tables into one FITS-LDAC file at `path` (LDAC_OBJECTS, ARCS).
void writeLensCatalog(const std::string& path, const LensRun& run,
                      const std::vector<std::string>& cards);
// What a run did and what it cost, for the terminal: systems drawn, skipped, rendered and with
// an arc, the sum of weights and the effective arcs, the CPU time per stage and per rendered
// system; `samplingName` and `outputPath` as the user gave them, `wallSec` on `ranks` ranks of
// `threads` threads each.
struct LensRunContext {
  std::string samplingName, outputPath;
  double wallSec = 0;
  int ranks = 1, threads = 1;
};
std::string lensRunSummary(const LensRun& run, const SimulationSetup& setup,
                           const LensRunContext& context);

// Writes the stamps as one float cube (plane k, 1-based, is system k - 1).
void writeLensStamps(const std::string& path, const LensRun& run, double pixelScaleArcsec);

}  // namespace octarc
