// `octarc calibrate` as a library: the studies of METHOD.md section 3 on simulate-lenses output
// (and, for the data side, a survey catalog of octarc detect), and the occupation-probability
// grid of section 4 made from the simulated arcs.
//
//   SimulationOutput (+ survey rows) --> lensing fractions, distributions, noise-only threshold,
//                                        the colour cut (a simulation with a second band)
//                                    --> occupation grid (finest connected binning, contour P)
//   --> calibrationTables() (FITS tables), calibrationPlots() (check-plots), the grid file
//
// The studies that simulate again (the threshold-count curve, the S/N floor) remake the
// simulation's own systems (calibration/SimulationOutput.h, checkRemade).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "octarc/calibration/ColourCut.h"
#include "octarc/calibration/GaussianFit.h"
#include "octarc/calibration/LensingFraction.h"
#include "octarc/calibration/NoiseThreshold.h"
#include "octarc/calibration/SimulationOutput.h"
#include "octarc/calibration/SnrFloor.h"
#include "octarc/calibration/ThresholdCount.h"
#include "octarc/calibration/Weights.h"
#include "octarc/core/Table.h"
#include "octarc/io/FitsTable.h"
#include "octarc/plot/CheckPlot.h"
#include "octarc/selection/BinningSearch.h"
#include "octarc/selection/GridFile.h"

namespace octarc {

struct CalibrationSettings {
  FractionCuts fractionCuts;
  // The occupation grid: axes (expressions on the systems' columns), the search space its arcs
  // are restricted to (empty: every simulated arc), contour level, the bins per axis searched,
  // and the tails left out of each axis range (quantileRange; no tail below 1 / tail arcs, where
  // it would leave out the least and greatest values).
  std::vector<std::string> gridAxes;  // empty: defaultAxisExpressions()
  std::string searchSpaceName, searchSpaceExpression;
  double gridLevel = 0.99;
  int minBinsPerAxis = 2, maxBinsPerAxis = 30;
  double axisTailFraction = 0.001;
  bool makeGrid = true;  // false: GRID_NAME NONE
  int histogramBins = 40;
  std::optional<NoiseThresholdSettings> noise;  // the noise-only study, when wanted
  // The threshold-count curve (simulates again), when wanted.
  std::optional<ThresholdCountSettings> thresholdCount;
  std::optional<SnrFloorSettings> snrFloor;  // the S/N floor (simulates again), when wanted
  // The colour cut study, run when the simulation has a second band (OCTBAND). Its arcs:
  // ARC_FOUND = 1, ARCNESS > colourCutArcnessMin, SNR_ISO > fractionCuts.snrMin, and in the
  // search space when one is given.
  ColourCutSettings colourCut;
  double colourCutArcnessMin = 0.10;
};

// A weighted histogram normalised over the values inside its range: the fractions (weight in
// the bin over the weight inside the range) sum to 1 when any value is inside; the values
// outside are counted apart.
struct Histogram {
  std::vector<double> edges;     // bins + 1, increasing
  std::vector<double> fraction;  // per bin
  std::int64_t values = 0;       // finite values given
  double effective = 0;          // their Kish effective number (calibration/Weights.h)
  std::int64_t outside = 0;      // of them, outside [lo, hi)
};
// `bins` equal bins on [lo, hi); NaN values are not counted. A value exactly on a printed edge
// is in the bin that edge opens. `weights`: one per value (SIM_WEIGHT), empty for 1 each.
Histogram normalisedHistogram(const std::vector<double>& values, double lo, double hi, int bins,
                              const std::vector<double>& weights = {});

// One distribution of METHOD.md section 3: a column of the simulated arcs (and of the survey
// objects when a survey catalog is given), with the rows it is taken over.
struct Distribution {
  std::string name;       // table and plot name, e.g. "ARCNESS"
  std::string column;     // the column
  std::string selection;  // in words, e.g. "E_IMAGE > 0.6 and SNR_ISO > 40"
  Histogram simulated;
  std::optional<Histogram> survey;
  std::vector<CutLine> cuts;
  // The skewnesses: a Gaussian fitted to the simulated histogram (calibration/GaussianFit.h).
  std::optional<GaussianFit> gaussian;
  bool simulatedOnly = false;  // a column survey catalogs do not have (no survey histogram)
};

// The occupation grid's outcome: the axes it was made on (some dropped when the contour could
// not stay connected on them all), every binning tried, and the grid when one connected.
struct GridOutcome {
  BinningSearchOptions options;          // the binnings searched
  std::vector<std::string> axes;         // the axes asked for
  std::vector<std::string> usedAxes;     // those of the grid (empty: no grid)
  std::vector<std::string> droppedAxes;  // in the order they were dropped
  // One binning search per set of axes tried (all axes with a range first, then one fewer each
  // time), with those axes.
  struct Search {
    std::vector<std::string> axes;
    BinningSearchResult result;
  };
  std::vector<Search> searches;
  WeightedCount samples;          // arcs in the search space the grid was filled with
  std::optional<SavedGrid> grid;  // none: no binning connected, too few arcs, or GRID_NAME NONE
  bool skipped = false;           // GRID_NAME NONE
  std::string warning;            // why there is no grid, or axes were dropped ("" when neither)
};

struct CalibrationResult {
  std::int64_t simulatedSystems = 0;  // drawn from the population (OCTNSYS)
  LensingFractions fractions;
  std::vector<Distribution> distributions;
  std::optional<NoiseThresholdResult> noise;
  std::optional<ThresholdCountCurve> thresholdCount;
  std::optional<SnrFloorResult> snrFloor;
  std::optional<ColourCutStudy> colourCut;  // with a second band
  WeightedCount arcSystems;                 // systems with an arc (ARC_FOUND = 1)
  GridOutcome grid;
};

// Runs every study. `survey`: rows of an octarc detect catalog (may be null). ConfigError for
// an axis or cut that does not parse or names an unknown column. Too few arcs, or none, is no
// error: every study is made, and the grid is made on fewer axes, or not at all
// (GridOutcome::warning says why).
CalibrationResult calibrate(const SimulationOutput& simulation, const Table* survey,
                            const CalibrationSettings& settings);

// The tables of the calibration file: LENSING_FRACTION, one DIST_<name> per distribution
// (DIST_COLOUR_DIFF: ARC_COLOUR_B - LENS_COLOUR_B of the colour cut's arcs, with a second band),
// NOISE_THRESHOLD, THRESHOLD_COUNT, SNR_FLOOR and COLOUR_CUT (when run) and GRID_BINNING (every
// binning tried).
std::vector<FitsTable> calibrationTables(const CalibrationResult& result);

// The check-plots, by CHECKPLOT_TYPE: ARCNESS, ANTIARCNESS, SKEW_MAJOR, SKEW_MINOR, E_IMAGE,
// SNR_ISO (the distributions), LENSING_FRACTION, NOISE_THRESHOLD, THRESHOLD_COUNT, SNR_FLOOR,
// COLOUR_CUT (the completeness of the cut against MAX), COLOUR_DIFF (the distribution of
// ARC_COLOUR_B - LENS_COLOUR_B), GRID_BINNING.
std::vector<std::string> calibrationPlotTypes();
// The plot of one type; ConfigError for an unknown type, or a study's plot (NOISE_THRESHOLD,
// THRESHOLD_COUNT, SNR_FLOOR, COLOUR_CUT, COLOUR_DIFF) without that study.
Plot calibrationPlot(const CalibrationResult& result, const std::string& type);

}  // namespace octarc
