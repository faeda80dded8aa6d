// What `octarc calibrate` writes and prints, on a result whose every figure is known: the tables
// of the calibration file, the check-plots and the summary.
//
// The result is calibrate() on a hand-made simulation of seven systems, six of them with an arc,
// made in a second band, and on a hand-made survey catalog, with 4-bin histograms. Each value,
// weight and colour is chosen so that the bins, fractions and colour-cut rows can be counted by
// hand (no value on a bin edge, weights and colours binary fractions). The studies that simulate
// again (noise-only threshold, threshold-count curve, S/N floor) and the binning search are set
// by hand in the result, so their tables and plots are checked against the values the test put
// there.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "CalibrationTestSupport.h"
#include "ExpectError.h"
#include "TestPaths.h"
#include "octarc/calibration/Calibration.h"
#include "octarc/calibration/CalibrationKeys.h"
#include "octarc/calibration/CalibrationSummary.h"
#include "octarc/calibration/Weights.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"
#include "octarc/selection/GridBinning.h"
#include "octarc/selection/OccupationGrid.h"

namespace octarc {
namespace {

constexpr std::int64_t kKnownSystemsDrawn = 200;  // OCTNSYS of the known simulation

// The systems of the known simulation: 6 with an arc (ARC_FOUND = 1) weighing 1 + 2 + 1 + 4 + 1
// + 2 = 11 (squares 27), one without. The rows with ARCNESS > 0.10 (the 2nd to 5th) weigh 2 + 1
// + 4 + 1 = 8 (squares 22), and so do the arcs of DIST_ARCNESS (e > 0.6, S/N > 40: the 1st, 2nd,
// 4th and 5th).
SimulationOutput knownArcsSimulation() {
  const double nan = std::nan("");
  SimulationOutput sim = test::simulationOf<10>(
      {"ARC_FOUND", "ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR", "E_IMAGE", "SNR_ISO",
       "SIM_WEIGHT", "ARC_COLOUR_g", "LENS_COLOUR_g"},
      {
          // Arcness below 0.10: in the lensing fraction and DIST_ARCNESS only.
          {1, 0.07, 0.00, -0.2, 0.1, 0.7, 50, 1, 0.0, 0.5},
          // Colour difference +0.25.
          {1, 0.12, 0.01, 0.0, -0.05, 0.8, 200, 2, 0.75, 0.5},
          // e = 0.45 and S/N = 10: not distorted, not in DIST_ARCNESS nor in the colour cut.
          {1, 0.20, 0.02, -0.1, -0.2, 0.45, 10, 1, 1.0, 0.5},
          // Colour difference -0.25.
          {1, 0.25, 0.04, 0.1, 0.03, 0.9, 1000, 4, 0.25, 0.5},
          // No arc colour: kept by every MAX of the colour cut.
          {1, 0.16, 0.03, 0.2, 0.2, 0.65, 45, 1, nan, 0.5},
          // No arc: in nothing.
          {0, 0.30, 0.05, 0.3, 0.3, 0.9, 80, 8, 0.0, 0.5},
          // An arc without measurements: in the lensing fractions' normalisation only.
          {1, nan, nan, nan, nan, nan, nan, 2, nan, nan},
      },
      kKnownSystemsDrawn);
  sim.band = "g";
  return sim;
}

// Three objects of an octarc detect catalog (no SIM_WEIGHT: 1 each).
Table knownSurvey() {
  Table t({test::column("ARCNESS"), test::column("ANTIARCNESS"), test::column("SKEW_MAJOR"),
           test::column("SKEW_MINOR"), test::column("E_IMAGE"), test::column("SNR_ISO")});
  const std::vector<std::array<double, 6>> rows = {
      {0.12, 0.015, -0.08, -0.15, 0.7, 60},  // in every distribution
      {0.05, 0.5, 0.0, 0.0, 0.9, 100},       // arcness 0.05: in DIST_ARCNESS only
      // e = 0.3: not in DIST_ARCNESS; its anti-arcness and s_a are outside the bins.
      {0.28, 0.10, 0.5, 0.15, 0.3, 30},
  };
  for (const auto& r : rows) std::copy(r.begin(), r.end(), t.appendRow());
  return t;
}

CalibrationSettings knownSettings() {
  CalibrationSettings s;
  s.histogramBins = 4;
  s.makeGrid = false;  // the binning search is set by hand (handMadeGrid)
  s.colourCut.maxLoMag = -0.5;
  s.colourCut.maxHiMag = 0.5;
  s.colourCut.stepMag = 0.25;
  s.colourCut.completenessLevels = {0.10, 0.50, 0.90};
  return s;
}

const CalibrationResult& knownResult() {
  static const CalibrationResult result = [] {
    const Table survey = knownSurvey();
    return calibrate(knownArcsSimulation(), &survey, knownSettings());
  }();
  return result;
}

NoiseThresholdResult handMadeNoise() {
  NoiseThresholdResult n;
  n.thresholdsSigma = {3.0, 3.5, 4.0, 4.5};
  n.realisationsWithObjects = {20, 6, 1, 0};
  n.meanObjects = {5.5, 0.375, 0.025, 0.0};
  n.noiseOnlyThresholdSigma = 4.5;
  return n;
}

ThresholdCountCurve handMadeThresholdCount() {
  ThresholdCountCurve c;
  // levels, drawn, rendered, with an arc, (arcness > 0.10: count, weight, squared weight),
  // fraction with its interval.
  c.rows = {{1, 500, 480, 100, {40, 50.0, 70.0}, {0.100, 0.085, 0.115}},
            {5, 500, 480, 120, {60, 75.0, 105.0}, {0.150, 0.130, 0.170}},
            {10, 500, 480, 122, {62, 77.5, 110.0}, {0.155, 0.135, 0.175}}};
  c.flattensAtLevels = 5;
  return c;
}

SnrFloorResult handMadeSnrFloor() {
  const double nan = std::nan("");
  SnrFloorResult f;
  f.systems = {11, 12, 13};
  f.referenceArcness = {0.11, 0.09, 0.12};
  f.weights = {1.0, 2.0, 1.0};
  f.effectiveArcs = 16.0 / 6.0;
  f.scaledToArcness = 0.10;
  f.noiseFactors = {0.5, 1.0, 2.0};
  f.foundPerFactor = {30, 28, 20};
  f.realisationsPerFactor = 30;  // 3 arcs x 10 realisations
  // S/N range, measurements, median, 20 % and 80 % quantiles, reliable.
  f.bins = {{5, 10, 0, nan, nan, nan, false},
            {10, 20, 25, 0.13, 0.09, 0.17, false},
            {20, 40, 30, 0.105, 0.085, 0.125, true},
            {40, 80, 40, 0.10, 0.095, 0.11, true}};
  f.measurements = 95;
  f.floorSnr = 20.0;
  return f;
}

BinningTrial trialOf(int bins, std::int64_t occupied, std::int64_t selected, double probability,
                     bool connected, std::int64_t isolated, std::int64_t components) {
  BinningTrial t;
  t.binsPerAxis = bins;
  t.occupiedBins = occupied;
  t.selectedBins = selected;
  t.selectedProbability = probability;
  t.connectivity = {connected, isolated, components};
  return t;
}

// A search on two axes that never connects, then on ARCNESS alone, finest connected at 3 bins,
// made up to agree with the five measured arcs (weights 1, 2, 1, 4, 1) on ARCNESS in [0.07, 0.26).
// The grid is theirs at 3 bins: 0.07 and 0.12 (weight 3), 0.16 (1), 0.20 and 0.25 (5); at P =
// 0.85 its contour takes the bins of 5 and 3 (8 / 9 of the weight), 2 of 3 occupied bins.
GridOutcome handMadeGrid() {
  GridOutcome g;
  g.options.level = 0.85;
  g.options.minBins = 2;
  g.options.maxBins = 4;
  g.axes = {"ARCNESS", "E_IMAGE"};
  GridOutcome::Search both;
  both.axes = g.axes;
  both.result.options = g.options;
  both.result.trials = {trialOf(2, 3, 2, 8.0 / 9.0, false, 2, 2),
                        trialOf(3, 4, 3, 8.0 / 9.0, false, 1, 2),
                        trialOf(4, 5, 4, 8.0 / 9.0, false, 2, 3)};
  GridOutcome::Search one;
  one.axes = {"ARCNESS"};
  one.result.options = g.options;
  one.result.trials = {trialOf(2, 2, 2, 1.0, true, 0, 1), trialOf(3, 3, 2, 8.0 / 9.0, true, 0, 1),
                       trialOf(4, 4, 3, 8.0 / 9.0, false, 1, 2)};
  one.result.finestConnected = 3;
  g.searches = {both, one};
  g.usedAxes = {"ARCNESS"};
  g.droppedAxes = {"E_IMAGE"};
  const std::vector<double> weights = {1, 2, 1, 4, 1};
  for (const double w : weights) g.samples.add(w);
  GridAxis arcness;
  arcness.expression = "ARCNESS";
  arcness.lo = 0.07;
  arcness.hi = 0.26;
  OccupationGrid grid = OccupationGrid::fill(GridBinning({arcness}).withBins(3),
                                             {{0.07, 0.12, 0.20, 0.25, 0.16}}, weights);
  const Contour contour = grid.contour(g.options.level);
  g.grid.emplace(SavedGrid{std::move(grid), contour, GridProvenance{}});
  return g;
}

// The known result with every study made and a grid.
const CalibrationResult& everyStudyResult() {
  static const CalibrationResult result = [] {
    CalibrationResult r = knownResult();
    r.noise = handMadeNoise();
    r.thresholdCount = handMadeThresholdCount();
    r.snrFloor = handMadeSnrFloor();
    r.grid = handMadeGrid();
    return r;
  }();
  return result;
}

// Checks -----------------------------------------------------------------------------------------

// Element by element; NaN expected is NaN found (a bound that is not there).
void expectSameDoubles(const std::vector<double>& found, const std::vector<double>& expected) {
  ASSERT_EQ(found.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::isnan(expected[i])) {
      EXPECT_TRUE(std::isnan(found[i])) << "[" << i << "] " << found[i];
    } else {
      EXPECT_DOUBLE_EQ(found[i], expected[i]) << "[" << i << "]";
    }
  }
}

std::vector<std::string> columnNames(const FitsTable& t) {
  std::vector<std::string> names;
  for (const FitsColumn& c : t.columns) names.push_back(c.name);
  return names;
}

std::vector<std::string> columnUnits(const FitsTable& t) {
  std::vector<std::string> units;
  for (const FitsColumn& c : t.columns) units.push_back(c.unit);
  return units;
}

std::vector<std::string> tableNames(const std::vector<FitsTable>& tables) {
  std::vector<std::string> names;
  for (const FitsTable& t : tables) names.push_back(t.name);
  return names;
}

const FitsTable* tableNamed(const std::vector<FitsTable>& tables, const std::string& name) {
  for (const FitsTable& t : tables) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

const Distribution* distributionNamed(const CalibrationResult& r, const std::string& name) {
  for (const Distribution& d : r.distributions) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

// `bins` equal bins on [lo, hi).
std::vector<double> equalBinEdges(double lo, double hi, int bins) {
  std::vector<double> edges;
  for (int k = 0; k <= bins; ++k) edges.push_back(lo + (hi - lo) * k / bins);
  return edges;
}

// The top of a range taken from fewer than 100 values: no tail is left out, and the greatest
// value is moved up to the next double so that it is inside [lo, hi) (quantileRange).
double justAbove(double greatest) {
  return std::nextafter(greatest, std::numeric_limits<double>::infinity());
}

// The weighted fraction f of rows whose Kish effective number is n, with its interval: the
// successes are f n (calibration/Weights.h).
FractionInterval expectedInterval(double fraction, double effective) {
  return clopperPearson(fraction * effective, effective);
}

void expectFractionColumns(const FitsTable& t, const std::vector<double>& fraction,
                           double effective) {
  expectSameDoubles(t.doubles("FRACTION"), fraction);
  const std::vector<double> lo = t.doubles("FRACTION_LO"), hi = t.doubles("FRACTION_HI"),
                            err = t.doubles("FRACTION_ERR");
  ASSERT_EQ(lo.size(), fraction.size());
  for (std::size_t i = 0; i < fraction.size(); ++i) {
    const FractionInterval expected = expectedInterval(fraction[i], effective);
    EXPECT_NEAR(lo[i], expected.lo, 1e-12) << i;
    EXPECT_NEAR(hi[i], expected.hi, 1e-12) << i;
    EXPECT_DOUBLE_EQ(err[i], 0.5 * (hi[i] - lo[i])) << i;
  }
}

// A distribution of the known result as counted by hand.
struct ExpectedDistribution {
  std::string name;
  std::string value;      // what is histogrammed (VALUE)
  std::string selection;  // the rows taken, in words (SELECT)
  double lo = 0, hi = 0;  // the 4 bins' range
  std::vector<double> simulated;
  std::int64_t simulatedValues = 0;
  double simulatedEffective = 0;
  std::vector<double> survey;  // empty: no survey histogram
  std::int64_t surveyOutside = 0;
  std::vector<CutLine> cuts;
  bool gaussian = false;  // the skewnesses carry a Gaussian fit
};

std::vector<ExpectedDistribution> expectedDistributions() {
  const double fourArcs = 8.0 * 8.0 / 22.0;  // Kish number of weights 1, 2, 4, 1 or 2, 1, 4, 1
  const std::string bright = "E_IMAGE > 0.6 and SNR_ISO > 40", arcs = "ARCNESS > 0.10";
  return {
      // 0.07 (weight 1), 0.12 (2), 0.16 (1), 0.25 (4) in bins of 0.075; survey 0.12 and 0.05.
      {"ARCNESS",
       "ARCNESS",
       bright,
       0.0,
       0.3,
       {1 / 8.0, 2 / 8.0, 1 / 8.0, 4 / 8.0},
       4,
       fourArcs,
       {0.5, 0.5, 0.0, 0.0},
       0,
       {{0.05, "a = 0.05"}, {0.10, "a = 0.10"}, {0.15, "a = 0.15"}},
       false},
      // 0.01 (2), 0.02 (1), 0.03 (1), 0.04 (4); survey 0.015 and 0.10 (outside).
      {"ANTIARCNESS",
       "ANTIARCNESS",
       arcs,
       0.01,
       justAbove(0.04),
       {2 / 8.0, 1 / 8.0, 1 / 8.0, 4 / 8.0},
       4,
       fourArcs,
       {1.0, 0.0, 0.0, 0.0},
       1,
       {},
       false},
      // -0.1 (1), 0.0 (2), 0.1 (4), 0.2 (1); survey -0.08 and 0.5 (outside).
      {"SKEW_MAJOR",
       "SKEW_MAJOR",
       arcs,
       -0.1,
       justAbove(0.2),
       {1 / 8.0, 2 / 8.0, 4 / 8.0, 1 / 8.0},
       4,
       fourArcs,
       {1.0, 0.0, 0.0, 0.0},
       1,
       {},
       true},
      // -0.2 (1), -0.05 (2), 0.03 (4), 0.2 (1); survey -0.15 and 0.15.
      {"SKEW_MINOR",
       "SKEW_MINOR",
       arcs,
       -0.2,
       justAbove(0.2),
       {1 / 8.0, 2 / 8.0, 4 / 8.0, 1 / 8.0},
       4,
       fourArcs,
       {0.5, 0.0, 0.0, 0.5},
       0,
       {},
       true},
      // 0.45 (1), 0.65 (1), 0.8 (2), 0.9 (4) in bins of 0.25; survey 0.7 and 0.3.
      {"E_IMAGE",
       "E_IMAGE",
       arcs,
       0.0,
       1.0,
       {0.0, 1 / 8.0, 1 / 8.0, 6 / 8.0},
       4,
       fourArcs,
       {0.0, 0.5, 0.5, 0.0},
       0,
       {{0.6, "e = 0.6"}},
       false},
      // log10 of 10 (1), 45 (1), 200 (2), 1000 (4); survey log10 60 and log10 30.
      {"SNR_ISO",
       "log10(SNR_ISO)",
       arcs,
       std::log10(10.0),
       justAbove(std::log10(1000.0)),
       {1 / 8.0, 1 / 8.0, 2 / 8.0, 4 / 8.0},
       4,
       fourArcs,
       {0.5, 0.5, 0.0, 0.0},
       0,
       {{std::log10(40.0), "S/N = 40"}},
       false},
      // The colour cut's arcs with both colours: -0.25 (4), +0.25 (2); no survey side. Its cuts
      // are the MAX of each completeness level that some MAX reaches (not the 10 % any MAX
      // keeps): 5 / 7 >= 50 % from -0.25, all from +0.25.
      {"COLOUR_DIFF",
       "ARC_COLOUR_g - LENS_COLOUR_g",
       "ARCNESS > 0.1 and SNR_ISO > 40",
       -0.25,
       justAbove(0.25),
       {4 / 6.0, 0.0, 0.0, 2 / 6.0},
       2,
       6.0 * 6.0 / 20.0,
       {},
       0,
       {{-0.25, "50%"}, {0.25, "90%"}},
       false},
  };
}

// Tables ------------------------------------------------------------------------------------------

// The tables the header lists, in its order, and a file can hold them all.
TEST(CalibrationTables, OneTablePerStudyMadeInTheDocumentedOrder) {
  EXPECT_EQ(
      tableNames(calibrationTables(knownResult())),
      (std::vector<std::string>{"LENSING_FRACTION", "DIST_ARCNESS", "DIST_ANTIARCNESS",
                                "DIST_SKEW_MAJOR", "DIST_SKEW_MINOR", "DIST_E_IMAGE",
                                "DIST_SNR_ISO", "DIST_COLOUR_DIFF", "COLOUR_CUT", "GRID_BINNING"}));
  const std::vector<FitsTable> every = calibrationTables(everyStudyResult());
  const std::vector<std::string> names = {
      "LENSING_FRACTION", "DIST_ARCNESS", "DIST_ANTIARCNESS", "DIST_SKEW_MAJOR", "DIST_SKEW_MINOR",
      "DIST_E_IMAGE",     "DIST_SNR_ISO", "DIST_COLOUR_DIFF", "NOISE_THRESHOLD", "THRESHOLD_COUNT",
      "SNR_FLOOR",        "COLOUR_CUT",   "GRID_BINNING"};
  EXPECT_EQ(tableNames(every), names);
  // Every column of a table holds its rows (writeFitsTables refuses them otherwise).
  for (const FitsTable& t : every) {
    for (const FitsColumn& c : t.columns) EXPECT_EQ(c.rows(), t.rows()) << t.name << " " << c.name;
  }
  const std::string path = (test::scratchDir() / "calibration.fits").string();
  writeFitsTables(path, every);
  EXPECT_EQ(listFitsTables(path), names);
}

// Rows per arcness bin, all and then distorted and bright: the weights of the arcs in the bin
// over the 11 of all arcs, with the interval of the Kish number 11^2 / 27.
TEST(CalibrationTables, LensingFractionOfKnownArcs) {
  const std::vector<FitsTable> tables = calibrationTables(knownResult());
  const FitsTable& t = tables.front();
  ASSERT_EQ(t.name, "LENSING_FRACTION");
  EXPECT_EQ(columnNames(t), (std::vector<std::string>{
                                "ARCNESS_LO", "ARCNESS_HI", "DISTORTED", "N_SYSTEMS", "WEIGHT",
                                "FRACTION", "FRACTION_LO", "FRACTION_HI", "FRACTION_ERR"}));
  EXPECT_EQ(columnUnits(t), std::vector<std::string>(9, ""));  // arcness and counts: no unit
  ASSERT_EQ(t.rows(), 6);
  const double nan = std::nan("");
  expectSameDoubles(t.doubles("ARCNESS_LO"), {0.05, 0.05, 0.10, 0.10, 0.15, 0.15});
  expectSameDoubles(t.doubles("ARCNESS_HI"), {0.10, 0.10, 0.15, 0.15, nan, nan});
  EXPECT_EQ(t.integers("DISTORTED"), (std::vector<std::int64_t>{0, 1, 0, 1, 0, 1}));
  // 0.07 | 0.12 | 0.16, 0.20 and 0.25, of which 0.20 has e = 0.45.
  EXPECT_EQ(t.integers("N_SYSTEMS"), (std::vector<std::int64_t>{1, 1, 1, 1, 3, 2}));
  const std::vector<double> weight = {1, 1, 2, 2, 6, 5};
  expectSameDoubles(t.doubles("WEIGHT"), weight);
  std::vector<double> fraction;
  for (const double w : weight) fraction.push_back(w / 11.0);
  expectFractionColumns(t, fraction, 121.0 / 27.0);
  EXPECT_EQ(t.integer("NSYSTEMS"), kKnownSystemsDrawn);  // drawn, not rows
  EXPECT_EQ(t.integer("NARCSYS"), 6);
  EXPECT_DOUBLE_EQ(t.number("WARCSYS"), 11.0);
  EXPECT_DOUBLE_EQ(t.number("NEFFARC"), 121.0 / 27.0);
}

TEST(CalibrationTables, DistributionsOfKnownArcsAndSurveyObjects) {
  const std::vector<FitsTable> tables = calibrationTables(knownResult());
  for (const ExpectedDistribution& e : expectedDistributions()) {
    SCOPED_TRACE(e.name);
    const FitsTable* t = tableNamed(tables, "DIST_" + e.name);
    ASSERT_NE(t, nullptr);
    const bool survey = !e.survey.empty();
    std::vector<std::string> columns = {"BIN_LO", "BIN_HI", "SIM_FRACTION"};
    if (survey) columns.push_back("SURVEY_FRACTION");
    EXPECT_EQ(columnNames(*t), columns);
    ASSERT_EQ(t->rows(), 4);
    const std::vector<double> edges = equalBinEdges(e.lo, e.hi, 4);
    expectSameDoubles(t->doubles("BIN_LO"), {edges.begin(), edges.end() - 1});
    expectSameDoubles(t->doubles("BIN_HI"), {edges.begin() + 1, edges.end()});
    // The colour difference is in magnitudes, as its plot's axis; the rest are pure numbers.
    const std::string unit = e.name == "COLOUR_DIFF" ? "mag" : "";
    EXPECT_EQ(t->column("BIN_LO").unit, unit);
    EXPECT_EQ(t->column("BIN_HI").unit, unit);
    expectSameDoubles(t->doubles("SIM_FRACTION"), e.simulated);
    EXPECT_EQ(t->text("VALUE"), e.value);
    EXPECT_EQ(t->text("SELECT"), e.selection);
    EXPECT_EQ(t->integer("NSIM"), e.simulatedValues);
    EXPECT_DOUBLE_EQ(t->number("NEFFSIM"), e.simulatedEffective);
    EXPECT_EQ(t->integer("NSIMOUT"), 0);
    EXPECT_EQ(t->hasKeyword("NSURVEY"), survey);
    if (survey) {
      expectSameDoubles(t->doubles("SURVEY_FRACTION"), e.survey);
      EXPECT_EQ(t->integer("NSURVEY"), 2);
      EXPECT_EQ(t->integer("NSURVOUT"), e.surveyOutside);
    }
    // The skewnesses' Gaussian fits: the result's, FWHM = 2 sqrt(2 ln 2) sigma, the mean inside
    // the range of the values fitted.
    EXPECT_EQ(t->hasKeyword("GAUSFWHM"), e.gaussian);
    if (e.gaussian) {
      const Distribution* d = distributionNamed(knownResult(), e.name);
      ASSERT_TRUE(d && d->gaussian);
      EXPECT_EQ(t->number("GAUSMEAN"), d->gaussian->mean);
      EXPECT_EQ(t->number("GAUSSIG"), d->gaussian->sigma);
      EXPECT_EQ(t->number("GAUSFWHM"), d->gaussian->fwhm);
      EXPECT_TRUE(t->logical("GAUSCONV"));
      EXPECT_NEAR(t->number("GAUSFWHM"),
                  2.0 * std::sqrt(2.0 * std::log(2.0)) * t->number("GAUSSIG"), 1e-12);
      EXPECT_GT(t->number("GAUSMEAN"), e.lo);
      EXPECT_LT(t->number("GAUSMEAN"), e.hi);
    }
  }
}

// Three arcs weighing 2 (difference +0.25), 4 (-0.25) and 1 (no arc colour, kept by every MAX).
TEST(CalibrationTables, ColourCutOfKnownColours) {
  const std::vector<FitsTable> tables = calibrationTables(knownResult());
  const FitsTable* t = tableNamed(tables, "COLOUR_CUT");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(columnNames(*t),
            (std::vector<std::string>{"COLOUR_MAX", "N_KEPT", "WEIGHT", "FRACTION", "FRACTION_LO",
                                      "FRACTION_HI", "FRACTION_ERR"}));
  EXPECT_EQ(columnUnits(*t), (std::vector<std::string>{"mag", "", "", "", "", "", ""}));
  ASSERT_EQ(t->rows(), 5);
  expectSameDoubles(t->doubles("COLOUR_MAX"), {-0.5, -0.25, 0.0, 0.25, 0.5});
  EXPECT_EQ(t->integers("N_KEPT"), (std::vector<std::int64_t>{1, 2, 2, 3, 3}));
  const std::vector<double> weight = {1, 5, 5, 7, 7};
  expectSameDoubles(t->doubles("WEIGHT"), weight);
  std::vector<double> fraction;
  for (const double w : weight) fraction.push_back(w / 7.0);
  expectFractionColumns(*t, fraction, 49.0 / 21.0);
  EXPECT_EQ(t->text("BAND"), "g");
  for (const char* cut : {"ARC_FOUND == 1", "ARCNESS > 0.1", "SNR_ISO > 40"}) {
    EXPECT_NE(t->text("SELECT").find(cut), std::string::npos) << t->text("SELECT");
  }
  EXPECT_EQ(t->integer("NARCS"), 3);
  EXPECT_DOUBLE_EQ(t->number("WARCS"), 7.0);
  EXPECT_DOUBLE_EQ(t->number("NEFFARCS"), 49.0 / 21.0);
  EXPECT_EQ(t->integer("NCOLOUR"), 2);
  // 10 %: the arc without colours alone (any MAX, undefined); 50 %: 5 / 7 from -0.25; 90 %: all
  // from +0.25.
  EXPECT_TRUE(std::isnan(t->number("MAXC10")));
  EXPECT_DOUBLE_EQ(t->number("MAXC50"), -0.25);
  EXPECT_DOUBLE_EQ(t->number("MAXC90"), 0.25);
}

// The studies set by hand come out as they went in, with what the tables derive from them.
TEST(CalibrationTables, HandMadeStudiesAndBinningSearch) {
  const std::vector<FitsTable> tables = calibrationTables(everyStudyResult());

  const FitsTable* noise = tableNamed(tables, "NOISE_THRESHOLD");
  ASSERT_NE(noise, nullptr);
  EXPECT_EQ(columnNames(*noise),
            (std::vector<std::string>{"THRESHOLD", "N_WITH_OBJECTS", "MEAN_OBJECTS"}));
  EXPECT_EQ(columnUnits(*noise), (std::vector<std::string>{"sigma", "", ""}));
  expectSameDoubles(noise->doubles("THRESHOLD"), {3.0, 3.5, 4.0, 4.5});
  EXPECT_EQ(noise->integers("N_WITH_OBJECTS"), (std::vector<std::int64_t>{20, 6, 1, 0}));
  expectSameDoubles(noise->doubles("MEAN_OBJECTS"), {5.5, 0.375, 0.025, 0.0});
  EXPECT_DOUBLE_EQ(noise->number("NOISETHR"), 4.5);
  EXPECT_FALSE(noise->logical("NOISELOW"));

  const FitsTable* count = tableNamed(tables, "THRESHOLD_COUNT");
  ASSERT_NE(count, nullptr);
  EXPECT_EQ(columnNames(*count),
            (std::vector<std::string>{"NLEVELS", "N_SYSTEMS", "N_RENDERED", "N_ARC", "N_ARCNESS",
                                      "WEIGHT", "NEFF_ARCNESS", "FRACTION", "FRACTION_LO",
                                      "FRACTION_HI", "FRACTION_ERR"}));
  EXPECT_EQ(columnUnits(*count), std::vector<std::string>(11, ""));
  EXPECT_EQ(count->integers("NLEVELS"), (std::vector<std::int64_t>{1, 5, 10}));
  EXPECT_EQ(count->integers("N_SYSTEMS"), (std::vector<std::int64_t>{500, 500, 500}));
  EXPECT_EQ(count->integers("N_RENDERED"), (std::vector<std::int64_t>{480, 480, 480}));
  EXPECT_EQ(count->integers("N_ARC"), (std::vector<std::int64_t>{100, 120, 122}));
  EXPECT_EQ(count->integers("N_ARCNESS"), (std::vector<std::int64_t>{40, 60, 62}));
  expectSameDoubles(count->doubles("WEIGHT"), {50.0, 75.0, 77.5});
  expectSameDoubles(count->doubles("NEFF_ARCNESS"),
                    {50.0 * 50.0 / 70.0, 75.0 * 75.0 / 105.0, 77.5 * 77.5 / 110.0});
  expectSameDoubles(count->doubles("FRACTION"), {0.100, 0.150, 0.155});
  expectSameDoubles(count->doubles("FRACTION_LO"), {0.085, 0.130, 0.135});
  expectSameDoubles(count->doubles("FRACTION_HI"), {0.115, 0.170, 0.175});
  expectSameDoubles(count->doubles("FRACTION_ERR"),
                    {0.5 * (0.115 - 0.085), 0.5 * (0.170 - 0.130), 0.5 * (0.175 - 0.135)});
  EXPECT_EQ(count->integer("FLATNLEV"), 5);

  const FitsTable* floorTable = tableNamed(tables, "SNR_FLOOR");
  ASSERT_NE(floorTable, nullptr);
  EXPECT_EQ(columnNames(*floorTable),
            (std::vector<std::string>{"SNR_LO", "SNR_HI", "N_MEASURED", "ARCNESS_MEDIAN",
                                      "ARCNESS_Q20", "ARCNESS_Q80", "RELIABLE"}));
  EXPECT_EQ(columnUnits(*floorTable), std::vector<std::string>(7, ""));
  const double nan = std::nan("");
  expectSameDoubles(floorTable->doubles("SNR_LO"), {5, 10, 20, 40});
  expectSameDoubles(floorTable->doubles("SNR_HI"), {10, 20, 40, 80});
  EXPECT_EQ(floorTable->integers("N_MEASURED"), (std::vector<std::int64_t>{0, 25, 30, 40}));
  expectSameDoubles(floorTable->doubles("ARCNESS_MEDIAN"), {nan, 0.13, 0.105, 0.10});
  expectSameDoubles(floorTable->doubles("ARCNESS_Q20"), {nan, 0.09, 0.085, 0.095});
  expectSameDoubles(floorTable->doubles("ARCNESS_Q80"), {nan, 0.17, 0.125, 0.11});
  EXPECT_EQ(floorTable->integers("RELIABLE"), (std::vector<std::int64_t>{0, 0, 1, 1}));
  EXPECT_DOUBLE_EQ(floorTable->number("SNRFLOOR"), 20.0);
  EXPECT_EQ(floorTable->integer("NARCS"), 3);
  EXPECT_DOUBLE_EQ(floorTable->number("NEFFARCS"), 16.0 / 6.0);
  EXPECT_EQ(floorTable->integer("NMEASURE"), 95);
  // Found in 30 + 28 + 20 of 3 factors x 30 realisations.
  EXPECT_DOUBLE_EQ(floorTable->number("FOUNDFRC"), 78.0 / 90.0);

  const FitsTable& binning = tables.back();
  ASSERT_EQ(binning.name, "GRID_BINNING");
  EXPECT_EQ(columnNames(binning),
            (std::vector<std::string>{"NAXES", "AXES", "BINS_PER_AXIS", "OCCUPIED", "SELECTED",
                                      "SELECTED_PROB", "CONNECTED", "ISOLATED", "COMPONENTS"}));
  EXPECT_EQ(columnUnits(binning), std::vector<std::string>(9, ""));
  EXPECT_EQ(binning.integers("NAXES"), (std::vector<std::int64_t>{2, 2, 2, 1, 1, 1}));
  EXPECT_EQ(binning.strings("AXES"),
            (std::vector<std::string>{"ARCNESS,E_IMAGE", "ARCNESS,E_IMAGE", "ARCNESS,E_IMAGE",
                                      "ARCNESS", "ARCNESS", "ARCNESS"}));
  EXPECT_EQ(binning.integers("BINS_PER_AXIS"), (std::vector<std::int64_t>{2, 3, 4, 2, 3, 4}));
  EXPECT_EQ(binning.integers("OCCUPIED"), (std::vector<std::int64_t>{3, 4, 5, 2, 3, 4}));
  EXPECT_EQ(binning.integers("SELECTED"), (std::vector<std::int64_t>{2, 3, 4, 2, 2, 3}));
  expectSameDoubles(binning.doubles("SELECTED_PROB"),
                    {8.0 / 9.0, 8.0 / 9.0, 8.0 / 9.0, 1.0, 8.0 / 9.0, 8.0 / 9.0});
  EXPECT_EQ(binning.integers("CONNECTED"), (std::vector<std::int64_t>{0, 0, 0, 1, 1, 0}));
  EXPECT_EQ(binning.integers("ISOLATED"), (std::vector<std::int64_t>{2, 1, 2, 0, 0, 1}));
  EXPECT_EQ(binning.integers("COMPONENTS"), (std::vector<std::int64_t>{2, 2, 3, 1, 1, 2}));
  EXPECT_EQ(binning.integer("FINEST"), 3);
  EXPECT_DOUBLE_EQ(binning.number("PLEVEL"), 0.85);
  EXPECT_EQ(binning.integer("NSAMPLES"), 5);
  EXPECT_DOUBLE_EQ(binning.number("NEFFSAMP"), 81.0 / 23.0);  // weights 1, 2, 1, 4, 1
  EXPECT_TRUE(binning.logical("GRIDMADE"));
  EXPECT_EQ(binning.integer("NGRIDAX"), 1);
  EXPECT_EQ(binning.text("GRIDAX1"), "ARCNESS");
  EXPECT_EQ(binning.integer("NDROPAX"), 1);
  EXPECT_EQ(binning.text("DROPAX1"), "E_IMAGE");
}

// GRID_NAME NONE: no binning tried, no grid, the level asked for still recorded.
TEST(CalibrationTables, NoGridAskedForHasAnEmptyBinningTable) {
  const std::vector<FitsTable> tables = calibrationTables(knownResult());
  const FitsTable& binning = tables.back();
  ASSERT_EQ(binning.name, "GRID_BINNING");
  EXPECT_EQ(binning.columns.size(), 9u);
  EXPECT_EQ(binning.rows(), 0);
  EXPECT_EQ(binning.integer("FINEST"), 0);
  EXPECT_DOUBLE_EQ(binning.number("PLEVEL"), knownSettings().gridLevel);
  EXPECT_EQ(binning.integer("NSAMPLES"), 0);
  EXPECT_FALSE(binning.logical("GRIDMADE"));
  EXPECT_EQ(binning.integer("NGRIDAX"), 0);
  EXPECT_EQ(binning.integer("NDROPAX"), 0);
}

// Plots ------------------------------------------------------------------------------------------

// The types the header lists, and each drawable: labelled, with series whose points match (n + 1
// edges for n steps), error bars around their points, and a finite point to draw.
TEST(CalibrationPlot, EveryListedTypeIsDrawnFromAResultWithEveryStudy) {
  EXPECT_EQ(
      calibrationPlotTypes(),
      (std::vector<std::string>{"ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR", "E_IMAGE",
                                "SNR_ISO", "LENSING_FRACTION", "NOISE_THRESHOLD", "THRESHOLD_COUNT",
                                "SNR_FLOOR", "COLOUR_CUT", "COLOUR_DIFF", "GRID_BINNING"}));
  for (const std::string& type : calibrationPlotTypes()) {
    SCOPED_TRACE(type);
    const Plot p = calibrationPlot(everyStudyResult(), type);
    EXPECT_FALSE(p.title.empty());
    EXPECT_FALSE(p.xLabel.empty());
    EXPECT_FALSE(p.yLabel.empty());
    ASSERT_FALSE(p.series.empty());
    bool finitePoint = false;
    for (const PlotSeries& s : p.series) {
      EXPECT_FALSE(s.label.empty());
      EXPECT_EQ(s.x.size(), s.y.size() + (s.steps ? 1 : 0)) << s.label;
      EXPECT_TRUE(s.yLow.empty() || s.yLow.size() == s.y.size()) << s.label;
      EXPECT_EQ(s.yLow.size(), s.yHigh.size()) << s.label;
      for (std::size_t i = 0; i < s.yLow.size(); ++i) {
        EXPECT_LE(s.yLow[i], s.y[i]) << s.label << " " << i;
        EXPECT_GE(s.yHigh[i], s.y[i]) << s.label << " " << i;
      }
      for (std::size_t i = 0; i < s.y.size(); ++i) {
        finitePoint = finitePoint || (std::isfinite(s.x[i]) && std::isfinite(s.y[i]));
        if (p.logX) {
          EXPECT_GT(s.x[i], 0.0) << s.label;
        }
      }
    }
    EXPECT_TRUE(finitePoint);
  }
}

// Each distribution: the simulated histogram (and the survey's) as steps over the bin edges,
// the Gaussian fit of the skewnesses sampled over the range, and the search spaces' cuts.
TEST(CalibrationPlot, DistributionsOfKnownArcsAndSurveyObjects) {
  for (const ExpectedDistribution& e : expectedDistributions()) {
    SCOPED_TRACE(e.name);
    const Plot p = calibrationPlot(knownResult(), e.name);
    EXPECT_EQ(p.title, e.name + " (" + e.selection + ")");
    const std::string xLabel = e.name == "SNR_ISO"       ? "log#d10#u S/N (ISO)"
                               : e.name == "COLOUR_DIFF" ? "ARC_COLOUR_g - LENS_COLOUR_g [mag]"
                                                         : e.name;
    EXPECT_EQ(p.xLabel, xLabel);
    EXPECT_EQ(p.yLabel, "fraction per bin");
    EXPECT_FALSE(p.logX);
    EXPECT_FALSE(p.logY);
    const std::vector<double> edges = equalBinEdges(e.lo, e.hi, 4);
    ASSERT_EQ(p.series.size(), 1u + (e.survey.empty() ? 0 : 1) + (e.gaussian ? 1 : 0));
    const PlotSeries& simulated = p.series[0];
    // 4 arcs of Kish number 64 / 22 = 2.9; 2 of 36 / 20 = 1.8.
    EXPECT_EQ(simulated.label, e.simulatedValues == 4 ? "simulated: 4 arcs (3 effective)"
                                                      : "simulated: 2 arcs (2 effective)");
    EXPECT_TRUE(simulated.steps);
    expectSameDoubles(simulated.x, edges);
    expectSameDoubles(simulated.y, e.simulated);
    EXPECT_TRUE(simulated.yLow.empty());
    if (!e.survey.empty()) {
      const PlotSeries& survey = p.series[1];
      EXPECT_EQ(survey.label, "survey objects (2)");
      EXPECT_TRUE(survey.steps);
      expectSameDoubles(survey.x, edges);
      expectSameDoubles(survey.y, e.survey);
    }
    if (e.gaussian) {
      const Distribution* d = distributionNamed(knownResult(), e.name);
      ASSERT_TRUE(d && d->gaussian);
      const GaussianFit& g = *d->gaussian;
      const PlotSeries& curve = p.series.back();
      char label[64];
      std::snprintf(label, sizeof label, "Gaussian fit, FWHM %.3f", g.fwhm);
      EXPECT_EQ(curve.label, label);
      EXPECT_FALSE(curve.steps);
      ASSERT_EQ(curve.x.size(), 201u);
      EXPECT_DOUBLE_EQ(curve.x.front(), e.lo);
      EXPECT_DOUBLE_EQ(curve.x.back(), e.hi);
      for (std::size_t k = 0; k < curve.x.size(); k += 50) {
        const double u = (curve.x[k] - g.mean) / g.sigma;
        EXPECT_NEAR(curve.y[k], g.amplitude * std::exp(-0.5 * u * u), 1e-12) << k;
      }
      // The fit follows the histogram: highest in the bin of half the weight.
      const std::size_t peak =
          std::size_t(std::max_element(curve.y.begin(), curve.y.end()) - curve.y.begin());
      EXPECT_GE(curve.x[peak], edges[1]);
      EXPECT_LE(curve.x[peak], edges[3]);
    }
    ASSERT_EQ(p.cuts.size(), e.cuts.size());
    for (std::size_t i = 0; i < e.cuts.size(); ++i) {
      EXPECT_DOUBLE_EQ(p.cuts[i].x, e.cuts[i].x) << i;
      EXPECT_EQ(p.cuts[i].label, e.cuts[i].label) << i;
    }
  }
}

// Steps over the arcness bins (the open last bin drawn 0.05 wide), all arcs and the distorted
// and bright ones, with their intervals as error bars.
TEST(CalibrationPlot, LensingFractionOfKnownArcs) {
  const Plot p = calibrationPlot(knownResult(), "LENSING_FRACTION");
  // 6 arcs of Kish number 121 / 27 = 4.5.
  EXPECT_NE(p.title.find("6 systems (4 effective) with an arc"), std::string::npos) << p.title;
  EXPECT_EQ(p.xLabel, "ARCNESS of the chosen arc");
  EXPECT_EQ(p.yLabel, "fraction of systems with an arc");
  ASSERT_EQ(p.series.size(), 2u);
  EXPECT_EQ(p.series[0].label, "all");
  EXPECT_EQ(p.series[1].label, "also e > 0.6, S/N > 40");
  const std::vector<std::vector<double>> weights = {{1, 2, 6}, {1, 2, 5}};
  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE(p.series[k].label);
    const PlotSeries& s = p.series[k];
    EXPECT_TRUE(s.steps);
    expectSameDoubles(s.x, {0.05, 0.10, 0.15, 0.20});
    ASSERT_EQ(s.y.size(), 3u);
    ASSERT_EQ(s.yLow.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      const FractionInterval expected = expectedInterval(weights[k][i] / 11.0, 121.0 / 27.0);
      EXPECT_DOUBLE_EQ(s.y[i], expected.fraction) << i;
      EXPECT_NEAR(s.yLow[i], expected.lo, 1e-12) << i;
      EXPECT_NEAR(s.yHigh[i], expected.hi, 1e-12) << i;
    }
  }
  EXPECT_TRUE(p.cuts.empty());
}

// The completeness against MAX with its intervals, and a line at the MAX of each level that
// some MAX reaches (the 10 % that any MAX keeps has none).
TEST(CalibrationPlot, ColourCutOfKnownColours) {
  const Plot p = calibrationPlot(knownResult(), "COLOUR_CUT");
  for (const char* part : {"in g", "3 arcs (2 effective)", "2 with both colours"}) {
    EXPECT_NE(p.title.find(part), std::string::npos) << p.title;
  }
  EXPECT_EQ(p.xLabel, "MAX of COLOUR_CUT g,MAX [mag]");
  EXPECT_EQ(p.yLabel, "fraction of simulated arcs kept");
  ASSERT_EQ(p.series.size(), 1u);
  const PlotSeries& s = p.series[0];
  EXPECT_NE(s.label.find("ARC_COLOUR_g - LENS_COLOUR_g <= MAX"), std::string::npos) << s.label;
  EXPECT_FALSE(s.steps);
  expectSameDoubles(s.x, {-0.5, -0.25, 0.0, 0.25, 0.5});
  const std::vector<double> weight = {1, 5, 5, 7, 7};
  ASSERT_EQ(s.y.size(), 5u);
  ASSERT_EQ(s.yLow.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const FractionInterval expected = expectedInterval(weight[i] / 7.0, 49.0 / 21.0);
    EXPECT_DOUBLE_EQ(s.y[i], expected.fraction) << i;
    EXPECT_NEAR(s.yLow[i], expected.lo, 1e-12) << i;
    EXPECT_NEAR(s.yHigh[i], expected.hi, 1e-12) << i;
  }
  ASSERT_EQ(p.cuts.size(), 2u);
  EXPECT_DOUBLE_EQ(p.cuts[0].x, -0.25);
  EXPECT_EQ(p.cuts[0].label, "50% kept from -0.25");
  EXPECT_DOUBLE_EQ(p.cuts[1].x, 0.25);
  EXPECT_EQ(p.cuts[1].label, "90% kept from 0.25");
}

TEST(CalibrationPlot, HandMadeStudiesAndBinningSearch) {
  const CalibrationResult& r = everyStudyResult();
  {
    const Plot p = calibrationPlot(r, "NOISE_THRESHOLD");
    EXPECT_EQ(p.xLabel, "detection threshold [sigma]");
    EXPECT_EQ(p.yLabel, "realisations with an object");
    ASSERT_EQ(p.series.size(), 1u);
    expectSameDoubles(p.series[0].x, {3.0, 3.5, 4.0, 4.5});
    expectSameDoubles(p.series[0].y, {20, 6, 1, 0});
    ASSERT_EQ(p.cuts.size(), 1u);
    EXPECT_DOUBLE_EQ(p.cuts[0].x, 4.5);
    EXPECT_EQ(p.cuts[0].label, "none from 4.50");
    // Objects even at the highest rung: no threshold, no line.
    CalibrationResult none = r;
    none.noise->noiseOnlyThresholdSigma = std::nan("");
    EXPECT_TRUE(calibrationPlot(none, "NOISE_THRESHOLD").cuts.empty());
  }
  {
    const Plot p = calibrationPlot(r, "THRESHOLD_COUNT");
    EXPECT_NE(p.title.find("ARCNESS > 0.10"), std::string::npos) << p.title;
    EXPECT_EQ(p.xLabel, "number of detection thresholds");
    EXPECT_EQ(p.yLabel, "fraction of simulated systems");
    ASSERT_EQ(p.series.size(), 1u);
    const PlotSeries& s = p.series[0];
    expectSameDoubles(s.x, {1, 5, 10});
    expectSameDoubles(s.y, {0.100, 0.150, 0.155});
    expectSameDoubles(s.yLow, {0.085, 0.130, 0.135});
    expectSameDoubles(s.yHigh, {0.115, 0.170, 0.175});
    ASSERT_EQ(p.cuts.size(), 1u);
    EXPECT_DOUBLE_EQ(p.cuts[0].x, 5.0);
    EXPECT_EQ(p.cuts[0].label, "flat from 5");
  }
  {
    const Plot p = calibrationPlot(r, "SNR_FLOOR");
    // 3 arcs of Kish number 16 / 6 = 2.7.
    for (const char* part : {"ARCNESS 0.10", "3 arcs (3 effective)"}) {
      EXPECT_NE(p.title.find(part), std::string::npos) << p.title;
    }
    EXPECT_EQ(p.xLabel, "S/N (ISO)");
    EXPECT_EQ(p.yLabel, "ARCNESS (scaled)");
    EXPECT_TRUE(p.logX);
    ASSERT_EQ(p.series.size(), 1u);
    const PlotSeries& s = p.series[0];
    // The bins with measurements, at their centres on the log axis.
    expectSameDoubles(s.x,
                      {std::sqrt(10.0 * 20.0), std::sqrt(20.0 * 40.0), std::sqrt(40.0 * 80.0)});
    expectSameDoubles(s.y, {0.13, 0.105, 0.10});
    expectSameDoubles(s.yLow, {0.09, 0.085, 0.095});
    expectSameDoubles(s.yHigh, {0.17, 0.125, 0.11});
    ASSERT_EQ(p.cuts.size(), 1u);
    EXPECT_DOUBLE_EQ(p.cuts[0].x, 20.0);
    EXPECT_EQ(p.cuts[0].label, "S/N floor 20");
  }
  {
    const Plot p = calibrationPlot(r, "GRID_BINNING");
    EXPECT_NE(p.title.find("5 arcs (4 effective)"), std::string::npos) << p.title;
    EXPECT_EQ(p.title.find("GRID_NAME NONE"), std::string::npos) << p.title;
    EXPECT_EQ(p.xLabel, "bins per axis");
    EXPECT_EQ(p.yLabel, "selected bins without a selected neighbour");
    ASSERT_EQ(p.series.size(), 2u);
    EXPECT_EQ(p.series[0].label, "2 axes");  // every axis asked for
    expectSameDoubles(p.series[0].x, {2, 3, 4});
    expectSameDoubles(p.series[0].y, {2, 1, 2});
    EXPECT_EQ(p.series[1].label, "1 axes (ARCNESS)");  // fewer: named
    expectSameDoubles(p.series[1].x, {2, 3, 4});
    expectSameDoubles(p.series[1].y, {0, 0, 1});
    ASSERT_EQ(p.cuts.size(), 1u);
    EXPECT_DOUBLE_EQ(p.cuts[0].x, 3.0);
    EXPECT_EQ(p.cuts[0].label, "finest connected: 3");
  }
}

// GRID_NAME NONE: nothing searched; a line at zero over the binnings that would have been tried.
TEST(CalibrationPlot, NoGridAskedForIsALineAtZero) {
  const Plot p = calibrationPlot(knownResult(), "GRID_BINNING");
  EXPECT_NE(p.title.find("GRID_NAME NONE"), std::string::npos) << p.title;
  ASSERT_EQ(p.series.size(), 1u);
  EXPECT_EQ(p.series[0].label, "no grid asked for");
  const CalibrationSettings s = knownSettings();
  expectSameDoubles(p.series[0].x, {double(s.minBinsPerAxis), double(s.maxBinsPerAxis)});
  expectSameDoubles(p.series[0].y, {0.0, 0.0});
  EXPECT_TRUE(p.cuts.empty());
}

TEST(CalibrationPlot, AnUnknownTypeOrAStudyNotMadeIsAnErrorNamingIt) {
  test::expectError<ConfigError>([] { calibrationPlot(knownResult(), "ARCNES"); },
                                 {"'ARCNES'", "not a calibration plot"});
  test::expectError<ConfigError>([] { calibrationPlot(knownResult(), ""); }, {"''"});
  for (const char* type : {"NOISE_THRESHOLD", "THRESHOLD_COUNT", "SNR_FLOOR"}) {
    test::expectError<ConfigError>([&] { calibrationPlot(knownResult(), type); }, {type, "off"});
  }
  // Without a second band there is no colour cut and no colour distribution.
  SimulationOutput oneBand = knownArcsSimulation();
  oneBand.band.clear();
  const CalibrationResult r = calibrate(oneBand, nullptr, knownSettings());
  EXPECT_FALSE(r.colourCut.has_value());
  for (const char* type : {"COLOUR_CUT", "COLOUR_DIFF"}) {
    test::expectError<ConfigError>([&] { calibrationPlot(r, type); }, {type, "second band"});
  }
  EXPECT_EQ(calibrationTables(r).size(), 1 + 6 + 1u);  // no DIST_COLOUR_DIFF nor COLOUR_CUT
  // A listed type that a result lacks is named as such, not as an unknown plot.
  test::expectError<ConfigError>([] { calibrationPlot(CalibrationResult{}, "ARCNESS"); },
                                 {"ARCNESS", "no such distribution"});
}

// No arc at all (documented as no error: every study is made, no grid): every table and plot is
// there, with empty histograms, fractions of 0 whose intervals are the whole range, and the
// binning plot saying that nothing was searched.
TEST(CalibrationOutputs, NoArcGivesEveryTableAndPlotWithNothingCounted) {
  SimulationOutput sim = knownArcsSimulation();
  const int found = sim.systems.findColumn("ARC_FOUND");
  for (std::int64_t row = 0; row < sim.systems.rows(); ++row) sim.systems.setValue(row, found, 0);
  CalibrationSettings settings = knownSettings();
  settings.makeGrid = true;
  const CalibrationResult r = calibrate(sim, nullptr, settings);
  const std::vector<FitsTable> tables = calibrationTables(r);
  EXPECT_EQ(tableNames(tables), tableNames(calibrationTables(knownResult())));

  const FitsTable& fraction = tables.front();
  EXPECT_EQ(fraction.integers("N_SYSTEMS"), std::vector<std::int64_t>(6, 0));
  expectSameDoubles(fraction.doubles("FRACTION"), std::vector<double>(6, 0.0));
  expectSameDoubles(fraction.doubles("FRACTION_LO"), std::vector<double>(6, 0.0));
  expectSameDoubles(fraction.doubles("FRACTION_HI"), std::vector<double>(6, 1.0));
  EXPECT_EQ(fraction.integer("NSYSTEMS"), kKnownSystemsDrawn);
  EXPECT_EQ(fraction.integer("NARCSYS"), 0);
  EXPECT_EQ(fraction.number("NEFFARC"), 0.0);
  for (const ExpectedDistribution& e : expectedDistributions()) {
    SCOPED_TRACE(e.name);
    const FitsTable* t = tableNamed(tables, "DIST_" + e.name);
    ASSERT_NE(t, nullptr);
    expectSameDoubles(t->doubles("SIM_FRACTION"), std::vector<double>(4, 0.0));
    EXPECT_EQ(t->integer("NSIM"), 0);
    EXPECT_EQ(t->number("NEFFSIM"), 0.0);
    const Plot p = calibrationPlot(r, e.name);
    ASSERT_FALSE(p.series.empty());
    EXPECT_EQ(p.series[0].label, "simulated: 0 arcs (0 effective)");
    expectSameDoubles(p.series[0].y, std::vector<double>(4, 0.0));
  }
  const FitsTable* colour = tableNamed(tables, "COLOUR_CUT");
  ASSERT_NE(colour, nullptr);
  EXPECT_EQ(colour->integer("NARCS"), 0);
  EXPECT_EQ(colour->integers("N_KEPT"), std::vector<std::int64_t>(5, 0));
  expectSameDoubles(colour->doubles("FRACTION_HI"), std::vector<double>(5, 1.0));
  EXPECT_TRUE(calibrationPlot(r, "COLOUR_CUT").cuts.empty());  // no MAX reaches a level
  EXPECT_FALSE(tables.back().logical("GRIDMADE"));

  const Plot binning = calibrationPlot(r, "GRID_BINNING");
  EXPECT_NE(binning.title.find("0 arcs (0 effective)"), std::string::npos) << binning.title;
  ASSERT_EQ(binning.series.size(), 1u);
  EXPECT_EQ(binning.series[0].label, "too few arcs: no binning searched");
  expectSameDoubles(binning.series[0].x,
                    {double(settings.minBinsPerAxis), double(settings.maxBinsPerAxis)});
  expectSameDoubles(binning.series[0].y, {0.0, 0.0});
  EXPECT_TRUE(binning.cuts.empty());
}

// Summary ----------------------------------------------------------------------------------------

std::string printedSummary(const CalibrationRun& run, const CalibrationResult& r) {
  testing::internal::CaptureStdout();
  printCalibrationSummary(run, r);
  return testing::internal::GetCapturedStdout();
}

// The line that starts with `start`, "" when none does.
std::string lineStartingWith(const std::string& text, const std::string& start) {
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    if (text.compare(at, start.size(), start) == 0) return text.substr(at, end - at);
    at = end + 1;
  }
  return "";
}

// The run that made everyStudyResult: the known settings and those of the studies set by hand.
CalibrationRun everyStudyRun() {
  CalibrationRun run;
  run.settings = knownSettings();
  run.settings.noise.emplace();
  run.settings.noise->realisations = 40;
  run.settings.noise->sizePix = 64;
  run.settings.noise->minAreaPix = 3;
  run.settings.thresholdCount.emplace();
  run.settings.thresholdCount->systems = 500;
  run.settings.snrFloor.emplace();
  run.settings.snrFloor->realisations = 10;
  return run;
}

TEST(CalibrationSummary, PrintsTheFiguresOfTheResultInOrder) {
  const std::string out = printedSummary(everyStudyRun(), everyStudyResult());
  EXPECT_NE(out.find("200 simulated systems, 6 systems (4 effective) with an arc"),
            std::string::npos)
      << out;

  // Each arcness bin: the fractions of all arcs and of the distorted and bright ones, each
  // with its interval as +(hi - f) -(f - lo), to 4 decimals.
  const std::vector<std::pair<std::string, std::array<double, 2>>> bins = {
      {"0.05-0.10", {1, 1}}, {"0.10-0.15", {2, 2}}, {"> 0.15", {6, 5}}};
  for (const auto& [range, weights] : bins) {
    SCOPED_TRACE(range);
    const std::string line = lineStartingWith(out, "  " + range + " ");
    ASSERT_FALSE(line.empty()) << out;
    double printed[6];
    ASSERT_EQ(std::sscanf(line.c_str() + 12, " %lf +%lf -%lf %lf +%lf -%lf", &printed[0],
                          &printed[1], &printed[2], &printed[3], &printed[4], &printed[5]),
              6)
        << line;
    for (std::size_t k = 0; k < 2; ++k) {
      const FractionInterval f = expectedInterval(weights[k] / 11.0, 121.0 / 27.0);
      EXPECT_NEAR(printed[3 * k], f.fraction, 0.51e-4) << line;
      EXPECT_NEAR(printed[3 * k + 1], f.hi - f.fraction, 0.51e-4) << line;
      EXPECT_NEAR(printed[3 * k + 2], f.fraction - f.lo, 0.51e-4) << line;
    }
  }

  // The Gaussian fits of the skewnesses, and of nothing else.
  for (const char* name : {"SKEW_MAJOR", "SKEW_MINOR"}) {
    const std::string line = lineStartingWith(out, std::string(name) + " of the arcs with ");
    ASSERT_FALSE(line.empty()) << out;
    double fwhm = 0, mean = 0;
    const std::size_t at = line.find("FWHM");
    ASSERT_NE(at, std::string::npos) << line;
    ASSERT_EQ(std::sscanf(line.c_str() + at, "FWHM %lf (mean %lf)", &fwhm, &mean), 2) << line;
    const Distribution* d = distributionNamed(knownResult(), name);
    ASSERT_TRUE(d && d->gaussian);
    EXPECT_NEAR(fwhm, d->gaussian->fwhm, 0.51e-3) << line;
    EXPECT_NEAR(mean, d->gaussian->mean, 0.51e-3) << line;
  }
  std::size_t fits = 0;
  for (std::size_t at = out.find("Gaussian fit"); at != std::string::npos;
       at = out.find("Gaussian fit", at + 1)) {
    ++fits;
  }
  EXPECT_EQ(fits, 2u) << out;

  EXPECT_NE(out.find("Noise-only threshold: 4.50 sigma (40 realisations of 64^2 pixels, "
                     "DETECT_MINAREA 3)"),
            std::string::npos)
      << out;

  // The threshold-count curve: the arcs with arcness > 0.10 count with their Kish numbers
  // 50^2 / 70 = 35.7, 75^2 / 105 = 53.6, 77.5^2 / 110 = 54.6.
  EXPECT_NE(out.find("(500 systems each, 480 rendered)"), std::string::npos) << out;
  for (const char* line : {"    1 levels  0.1000 +0.0150 -0.0150  (40 arcs (36 effective))",
                           "    5 levels  0.1500 +0.0200 -0.0200  (60 arcs (54 effective))",
                           "   10 levels  0.1550 +0.0200 -0.0200  (62 arcs (55 effective))",
                           "  flat (within 1 sigma of the most levels) from 5 levels"}) {
    EXPECT_NE(out.find(std::string(line) + "\n"), std::string::npos) << line << "\n" << out;
  }

  // The S/N floor (through std::cout): the bins with measurements and the floor.
  EXPECT_NE(out.find("S/N floor (3 arcs (3 effective) scaled to ARCNESS 0.10, 10 noise "
                     "realisations per noise factor)"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("0.1300  0.0900  0.1700  unreliable\n"), std::string::npos) << out;
  EXPECT_NE(out.find("0.1050  0.0850  0.1250\n"), std::string::npos) << out;
  EXPECT_NE(out.find("0.1000  0.0950  0.1100\n"), std::string::npos) << out;
  EXPECT_EQ(out.find("5.0-10.0"), std::string::npos) << out;  // the empty bin
  EXPECT_NE(out.find("arcness unreliable below S/N 20.0"), std::string::npos) << out;

  // The colour cut: 3 arcs of Kish number 49 / 21 = 2.3, the MAX of each level, and the kept
  // fraction every 0.25 mag (1 / 7, 5 / 7, 5 / 7, 1, 1).
  EXPECT_NE(out.find("Colour cut COLOUR_CUT g,MAX on 3 arcs (2 effective)"), std::string::npos)
      << out;
  EXPECT_NE(out.find("2 with both colours"), std::string::npos) << out;
  for (const char* line :
       {"   10% of the arcs kept from MAX = any\n", "   50% of the arcs kept from MAX = -0.250\n",
        "   90% of the arcs kept from MAX = 0.250\n", "      -0.50  0.1429 ",
        "      -0.25  0.7143 ", "       0.00  0.7143 ", "       0.25  1.0000 ",
        "       0.50  1.0000 "}) {
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
  }

  EXPECT_NE(out.find("Occupation grid: 5 arcs (4 effective), 1 axes, 3 bins per axis (finest "
                     "connected at P = 0.85), 2 of 3 occupied bins selected\n"),
            std::string::npos)
      << out;

  // The sections in the order of the header, the S/N floor's among them.
  std::size_t previous = 0;
  for (const char* section :
       {"simulated systems", "Lensing fraction", "SKEW_MAJOR of the arcs", "Noise-only threshold",
        "against the number of thresholds", "S/N floor (", "Colour cut", "Occupation grid"}) {
    const std::size_t at = out.find(section);
    ASSERT_NE(at, std::string::npos) << section;
    EXPECT_GE(at, previous) << section << "\n" << out;
    previous = at;
  }
}

// Without the studies that simulate again, none of them is printed; with GRID_NAME NONE and with
// no arc for the grid, the grid line says why there is no grid.
TEST(CalibrationSummary, PrintsOnlyTheStudiesMade) {
  CalibrationRun run;
  run.settings = knownSettings();
  const std::string out = printedSummary(run, knownResult());
  for (const char* absent : {"Noise-only", "against the number of thresholds", "S/N floor"}) {
    EXPECT_EQ(out.find(absent), std::string::npos) << absent << "\n" << out;
  }
  EXPECT_NE(out.find("Colour cut COLOUR_CUT g,MAX"), std::string::npos) << out;
  EXPECT_NE(out.find("Occupation grid: none (GRID_NAME NONE)\n"), std::string::npos) << out;

  CalibrationResult gridWithoutArcs = knownResult();
  gridWithoutArcs.grid = GridOutcome();
  EXPECT_NE(
      printedSummary(run, gridWithoutArcs).find("Occupation grid: none (0 arcs (0 effective))\n"),
      std::string::npos);
}

}  // namespace
}  // namespace octarc
