// The calibration studies on cases with known answers: lensing fractions of a hand-made systems
// table (unit weights and SIM_WEIGHT), the Clopper-Pearson intervals against values computed
// apart, normalised (weighted) histograms, the distributions and grid of a handful of arcs (the
// grid on fewer axes, or none), and the noise-only threshold against the distribution of the
// largest of R N standard normal values (no filter, DETECT_MINAREA 1).
#include "octarc/calibration/Calibration.h"

#include <gtest/gtest.h>

#include <array>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "CalibrationTestSupport.h"
#include "octarc/calibration/LensingFraction.h"
#include "octarc/calibration/NoiseThreshold.h"
#include "octarc/calibration/Weights.h"
#include "octarc/core/Error.h"
#include "octarc/selection/GridBinning.h"

namespace octarc {
namespace {

using test::column;
using test::handfulSimulation;

// Systems: (ARC_FOUND, ARCNESS, E_IMAGE, SNR_ISO).
Table systemsTable(const std::vector<std::array<double, 4>>& rows) {
  Table t({column("ARC_FOUND"), column("ARCNESS"), column("E_IMAGE"), column("SNR_ISO")});
  for (const auto& r : rows) std::copy(r.begin(), r.end(), t.appendRow());
  return t;
}

TEST(LensingFraction, CountsAndBinomialErrorsOfAHandMadeTable) {
  const double nan = std::nan("");
  // 8 systems with an arc, 2 without (their arcness must not count).
  const Table t = systemsTable({{1, 0.07, 0.7, 50},
                                {1, 0.08, 0.5, 50},
                                {1, 0.12, 0.8, 100},
                                {1, 0.14, 0.8, 30},
                                {1, 0.20, 0.9, 60},
                                {1, 0.02, 0.9, 60},
                                {1, 0.10, 0.61, 40.5},  // on the bin edge: 0.10-0.15
                                {1, nan, nan, nan},
                                {0, 0.30, 0.9, 90},
                                {0, nan, nan, nan}});
  const LensingFractions f = lensingFractions(t);
  EXPECT_EQ(f.simulatedSystems, 10);
  EXPECT_EQ(f.arcSystems.count, 8);
  EXPECT_DOUBLE_EQ(f.arcSystems.effective(), 8.0);  // no SIM_WEIGHT: 1 each
  ASSERT_EQ(f.rows.size(), 6u);
  const std::int64_t expected[6] = {2, 1, 3, 2, 1, 1};  // per bin: all, distorted and bright
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(f.rows[i].systems, expected[i]) << i;
    const double p = expected[i] / 8.0;
    EXPECT_DOUBLE_EQ(f.rows[i].fraction.fraction, p);
    // The exact binomial interval of k of 8.
    const FractionInterval cp = clopperPearson(double(expected[i]), 8.0);
    EXPECT_DOUBLE_EQ(f.rows[i].fraction.lo, cp.lo);
    EXPECT_DOUBLE_EQ(f.rows[i].fraction.hi, cp.hi);
    EXPECT_LT(f.rows[i].fraction.lo, p);
    EXPECT_GT(f.rows[i].fraction.hi, p);
  }
  EXPECT_EQ(f.rows[4].arcnessLo, 0.15);
  EXPECT_TRUE(std::isinf(f.rows[4].arcnessHi));
  EXPECT_TRUE(f.rows[5].distortedAndBright);
}

// The same systems with weights: each fraction is the weight in the bin over the weight of the
// systems with an arc, its interval that of k = f n in n = (sum w)^2 / sum w^2 trials.
TEST(LensingFraction, WeightedFractionsAreWeightSumsOverTheArcs) {
  const double nan = std::nan("");
  ColumnSpec w = column("SIM_WEIGHT");
  Table t({column("ARC_FOUND"), column("ARCNESS"), column("E_IMAGE"), column("SNR_ISO"), w});
  const std::vector<std::array<double, 5>> rows = {
      {1, 0.07, 0.7, 50, 2.0},   // 0.05-0.10, distorted and bright
      {1, 0.08, 0.5, 50, 4.0},   // 0.05-0.10
      {1, 0.12, 0.8, 100, 1.0},  // 0.10-0.15, distorted and bright
      {1, 0.20, 0.9, 60, 8.0},   // > 0.15, distorted and bright
      {1, 0.02, 0.9, 60, 1.0},   // below every bin
      {1, nan, nan, nan, 4.0},   // an arc without arcness: in the normalisation only
      {0, 0.30, 0.9, 90, 100.0}  // no arc: nowhere
  };
  for (const auto& r : rows) std::copy(r.begin(), r.end(), t.appendRow());
  const LensingFractions f = lensingFractions(t);
  // sum w = 20, sum w^2 = 4 + 16 + 1 + 64 + 1 + 16 = 102: n = 400 / 102.
  EXPECT_EQ(f.arcSystems.count, 6);
  EXPECT_DOUBLE_EQ(f.arcSystems.weightSum, 20.0);
  EXPECT_DOUBLE_EQ(f.arcSystems.weightSquaredSum, 102.0);
  const double n = 400.0 / 102.0;
  EXPECT_DOUBLE_EQ(f.arcSystems.effective(), n);
  const double weight[6] = {6.0, 2.0, 1.0, 1.0, 8.0, 8.0};  // per bin: all, distorted
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_DOUBLE_EQ(f.rows[i].weight, weight[i]) << i;
    EXPECT_DOUBLE_EQ(f.rows[i].fraction.fraction, weight[i] / 20.0) << i;
    const FractionInterval cp = clopperPearson(weight[i] / 20.0 * n, n);
    EXPECT_NEAR(f.rows[i].fraction.lo, cp.lo, 1e-12) << i;
    EXPECT_NEAR(f.rows[i].fraction.hi, cp.hi, 1e-12) << i;
  }
  EXPECT_EQ(f.rows[0].systems, 2);  // the integer counts are kept beside the weights
}

// Clopper-Pearson at 68.27 % two-sided against values computed apart: 0 of 10 has the upper
// bound 1 - 0.158655^(1/10) = 0.16815 (the textbook closed form), the others from
// scipy.stats.beta.ppf(0.158650, k, n - k + 1) and beta.ppf(0.841350, k + 1, n - k).
TEST(ClopperPearson, BoundsMatchValuesComputedApart) {
  const FractionInterval none = clopperPearson(0, 10);
  EXPECT_EQ(none.fraction, 0.0);
  EXPECT_EQ(none.lo, 0.0);
  EXPECT_NEAR(none.hi, 1.0 - std::pow(0.5 * (1.0 - 0.6827), 0.1), 1e-9);
  EXPECT_NEAR(none.hi, 0.1681519408858844, 1e-9);
  const FractionInterval three = clopperPearson(3, 10);
  EXPECT_NEAR(three.lo, 0.14166978253195195, 1e-9);
  EXPECT_NEAR(three.hi, 0.5082658513353708, 1e-9);
  const FractionInterval all = clopperPearson(10, 10);
  EXPECT_NEAR(all.lo, 0.8318480591141156, 1e-9);
  EXPECT_EQ(all.hi, 1.0);
  const FractionInterval five = clopperPearson(5, 20);
  EXPECT_NEAR(five.lo, 0.1465913644970485, 1e-9);
  EXPECT_NEAR(five.hi, 0.3837502626349576, 1e-9);
  // Non-integer trials and successes (a weighted fraction): the same Beta quantiles.
  const FractionInterval real = clopperPearson(2.5, 7.3);
  EXPECT_NEAR(real.lo, 0.14614139378586374, 1e-9);
  EXPECT_NEAR(real.hi, 0.592901837599443, 1e-9);
  // Nothing to go on: the whole range.
  const FractionInterval empty = clopperPearson(0, 0);
  EXPECT_EQ(empty.lo, 0.0);
  EXPECT_EQ(empty.hi, 1.0);
  EXPECT_THROW(clopperPearson(11, 10), ConfigError);
  EXPECT_EQ(intervalText(none), "+0.1682 -0.0000");
  EXPECT_EQ(countWithEffective(496, 411.6), "496 arcs (412 effective)");
}

TEST(LensingFraction, AMissingColumnIsNamed) {
  Table t({column("ARC_FOUND"), column("ARCNESS")});
  try {
    lensingFractions(t);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("E_IMAGE"), std::string::npos);
  }
}

TEST(NormalisedHistogram, FractionsOfTheFiniteValues) {
  const Histogram h = normalisedHistogram({0.05, 0.15, 0.15, 0.25, 1.5, std::nan("")}, 0.0, 0.3, 3);
  ASSERT_EQ(h.edges.size(), 4u);
  EXPECT_DOUBLE_EQ(h.edges[3], 0.3);
  EXPECT_EQ(h.values, 5);  // the NaN is not a value; 1.5 is, outside the range
  EXPECT_EQ(h.outside, 1);
  EXPECT_DOUBLE_EQ(h.fraction[0], 0.25);
  EXPECT_DOUBLE_EQ(h.fraction[1], 0.5);
  EXPECT_DOUBLE_EQ(h.fraction[2], 0.25);
  // A value on a printed edge is in the bin the edge opens, whatever the rounding of floor().
  const Histogram e = normalisedHistogram({0.1, 0.2}, 0.0, 0.3, 3);
  EXPECT_DOUBLE_EQ(e.fraction[0], 0.0);
  EXPECT_DOUBLE_EQ(e.fraction[1], 0.5);
  EXPECT_DOUBLE_EQ(e.fraction[2], 0.5);
}

TEST(NormalisedHistogram, WeightedFractionsAndTheEffectiveNumber) {
  const Histogram h =
      normalisedHistogram({0.05, 0.15, 0.25, 1.5, std::nan("")}, 0.0, 0.3, 3, {1, 2, 5, 4, 7});
  EXPECT_EQ(h.values, 4);
  EXPECT_EQ(h.outside, 1);
  // Inside: weights 1, 2, 5 (8 in all); the effective number is over every finite value.
  EXPECT_DOUBLE_EQ(h.fraction[0], 1.0 / 8.0);
  EXPECT_DOUBLE_EQ(h.fraction[1], 2.0 / 8.0);
  EXPECT_DOUBLE_EQ(h.fraction[2], 5.0 / 8.0);
  EXPECT_DOUBLE_EQ(h.effective, 144.0 / 46.0);
  EXPECT_THROW(normalisedHistogram({0.1}, 0.0, 1.0, 2, {1, 2}), ConfigError);
}

// Arcs with values drawn at random on every axis (arcness above 0.1, so every distribution
// takes them all).
std::vector<std::array<double, 8>> randomArcs(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::array<double, 8>> rows;
  for (int i = 0; i < n; ++i) {
    rows.push_back({1.0, 0.11 + 0.2 * u(rng), 0.05 * u(rng), u(rng) - 0.5, u(rng) - 0.5,
                    0.3 + 0.6 * u(rng), 20.0 + 200.0 * u(rng), 1.0 + 3.0 * u(rng)});
  }
  return rows;
}

// 14 arcs: no histogram may be empty while its legend counts arcs. A range from the 1 % and
// 99 % quantiles (interpolated between order statistics) leaves the least and the greatest value
// outside whenever there are fewer than 100 values, and with two values both: below 1 / tail
// values the range is the values' own.
TEST(Calibrate, AHandfulOfArcsFillsEveryHistogram) {
  const SimulationOutput sim = handfulSimulation(randomArcs(14, 7), 1000);
  CalibrationSettings s;
  const CalibrationResult r = calibrate(sim, nullptr, s);
  EXPECT_EQ(r.simulatedSystems, 1000);
  EXPECT_EQ(r.arcSystems.count, 14);
  for (const Distribution& d : r.distributions) {
    if (d.name == "ARCNESS" || d.name == "E_IMAGE") continue;  // fixed ranges, cut on e, S/N
    EXPECT_EQ(d.simulated.values, 14) << d.name;
    EXPECT_EQ(d.simulated.outside, 0) << d.name;
    const double sum =
        std::accumulate(d.simulated.fraction.begin(), d.simulated.fraction.end(), 0.0);
    EXPECT_NEAR(sum, 1.0, 1e-12) << d.name;
    EXPECT_GT(d.simulated.effective, 1.0) << d.name;
    EXPECT_LT(d.simulated.effective, 14.0) << d.name;  // unequal weights
  }
}

// Two arcs: both in every histogram and in the grid (an interpolated 0.1 % tail would have left
// both outside: a grid with no arc in a bin, an error).
TEST(Calibrate, TwoArcsAreInTheirHistogramsAndGrid) {
  const CalibrationSettings s;
  const CalibrationResult r = calibrate(handfulSimulation(randomArcs(2, 5), 100), nullptr, s);
  for (const Distribution& d : r.distributions) {
    if (d.name == "ARCNESS" || d.name == "E_IMAGE") continue;
    EXPECT_EQ(d.simulated.outside, 0) << d.name;
    EXPECT_NEAR(std::accumulate(d.simulated.fraction.begin(), d.simulated.fraction.end(), 0.0), 1.0,
                1e-12)
        << d.name;
  }
  ASSERT_TRUE(r.grid.grid.has_value()) << r.grid.warning;
  EXPECT_EQ(r.grid.grid->grid.binnedCount(), 2);
  EXPECT_EQ(r.grid.grid->grid.outsideCount(), 0);
}

// 40 arcs scattered over six axes cannot keep a contour at 0.99 connected at any binning (the
// most probable bins are lone); on fewer axes they can: the grid is made on those, saying which
// were dropped, and the studies are all there.
TEST(Calibrate, AGridThatCannotConnectOnSixAxesIsMadeOnFewer) {
  const SimulationOutput sim = handfulSimulation(randomArcs(40, 11), 5000);
  CalibrationSettings s;
  const CalibrationResult r = calibrate(sim, nullptr, s);
  const GridOutcome& g = r.grid;
  ASSERT_GE(g.searches.size(), 2u);
  EXPECT_EQ(g.searches.front().axes.size(), 6u);
  EXPECT_EQ(g.searches.front().result.finestConnected, 0);  // not on six axes
  ASSERT_TRUE(g.grid.has_value());
  EXPECT_LT(g.usedAxes.size(), 6u);
  EXPECT_EQ(g.usedAxes.size() + g.droppedAxes.size(), 6u);
  EXPECT_EQ(g.grid->grid.binning().dimensions(), int(g.usedAxes.size()));
  EXPECT_EQ(g.grid->provenance.droppedAxes, g.droppedAxes);
  EXPECT_GT(g.searches.back().result.finestConnected, 0);
  EXPECT_EQ(g.samples.count, 40);
  EXPECT_NE(g.warning.find("40 arcs ("), std::string::npos) << g.warning;
  EXPECT_NE(g.warning.find("dropped " + g.droppedAxes.front()), std::string::npos) << g.warning;
  EXPECT_NE(g.warning.find("GRID_NAME NONE"), std::string::npos) << g.warning;
  // The grid's probabilities are the arcs' weights over the binned weight.
  double binned = 0;
  for (const GridBin& b : g.grid->grid.bins()) {
    binned += b.weight;
    EXPECT_DOUBLE_EQ(b.probability, b.weight / g.grid->grid.binnedWeight());
  }
  EXPECT_NEAR(binned, g.grid->grid.binnedWeight(), 1e-9);
  // Every binning tried is in GRID_BINNING, with its axes.
  const std::vector<FitsTable> tables = calibrationTables(r);
  const FitsTable& binning = tables.back();
  ASSERT_EQ(binning.name, "GRID_BINNING");
  EXPECT_EQ(binning.integer("NDROPAX"), std::int64_t(g.droppedAxes.size()));
  EXPECT_EQ(binning.integer("NGRIDAX"), std::int64_t(g.usedAxes.size()));
  EXPECT_EQ(binning.strings("AXES").front(),
            "ARCNESS,ANTIARCNESS,SKEW_MAJOR,SKEW_MINOR,E_IMAGE,log10(SNR_ISO)");
  // And every check-plot can be drawn from it.
  for (const char* type :
       {"ARCNESS", "ANTIARCNESS", "SNR_ISO", "LENSING_FRACTION", "GRID_BINNING"}) {
    EXPECT_FALSE(calibrationPlot(r, type).series.empty()) << type;
  }
}

// An axis whose values are all equal has no range: it is dropped first, and said so.
TEST(Calibrate, AnAxisWithoutARangeIsDroppedFirst) {
  std::vector<std::array<double, 8>> rows = randomArcs(40, 11);
  for (auto& r : rows) r[4] = 0.0;  // SKEW_MINOR
  CalibrationSettings s;
  s.gridAxes = {"SKEW_MINOR", "ARCNESS"};
  s.gridLevel = 0.9;
  const CalibrationResult r = calibrate(handfulSimulation(rows, 5000), nullptr, s);
  ASSERT_TRUE(r.grid.grid.has_value()) << r.grid.warning;
  EXPECT_EQ(r.grid.usedAxes, (std::vector<std::string>{"ARCNESS"}));
  EXPECT_EQ(r.grid.droppedAxes, (std::vector<std::string>{"SKEW_MINOR"}));
  EXPECT_NE(r.grid.warning.find("dropped SKEW_MINOR (no range)"), std::string::npos)
      << r.grid.warning;
}

// No arc at all: no error; every study is made, no grid, a warning that counts the arcs.
TEST(Calibrate, NoArcMakesEveryStudyAndNoGrid) {
  std::vector<std::array<double, 8>> rows = randomArcs(5, 3);
  for (auto& r : rows) r[0] = 0.0;
  const CalibrationSettings s;
  const CalibrationResult r = calibrate(handfulSimulation(rows, 50), nullptr, s);
  EXPECT_EQ(r.arcSystems.count, 0);
  EXPECT_FALSE(r.grid.grid.has_value());
  EXPECT_NE(r.grid.warning.find("0 arcs (0 effective)"), std::string::npos) << r.grid.warning;
  for (const FractionRow& row : r.fractions.rows) {
    EXPECT_EQ(row.fraction.fraction, 0.0);
    EXPECT_EQ(row.fraction.hi, 1.0);  // nothing known
  }
  EXPECT_EQ(calibrationTables(r).size(), 1 + r.distributions.size() + 1);
  EXPECT_FALSE(calibrationPlot(r, "GRID_BINNING").series.empty());
}

// GRID_NAME NONE: no grid searched or made, and no warning.
TEST(Calibrate, NoGridAskedForIsNone) {
  CalibrationSettings s;
  s.makeGrid = false;
  const CalibrationResult r = calibrate(handfulSimulation(randomArcs(40, 11), 5000), nullptr, s);
  EXPECT_TRUE(r.grid.skipped);
  EXPECT_FALSE(r.grid.grid.has_value());
  EXPECT_TRUE(r.grid.searches.empty());
  EXPECT_TRUE(r.grid.warning.empty());
}

// Without a filter and with DETECT_MINAREA 1, the noise-only threshold is the first rung at or
// above the largest of R N standard normal values, whose distribution is Phi(t)^(R N): with a
// fixed seed, it must fall between that distribution's 0.5 % and 99.5 % points (plus a rung).
TEST(NoiseThreshold, WhiteNoiseFollowsTheDistributionOfTheLargestValue) {
  NoiseThresholdSettings s;
  s.sizePix = 64;
  s.realisations = 40;
  s.minAreaPix = 1;
  s.loSigma = 2.0;
  s.hiSigma = 7.0;
  s.stepSigma = 0.01;
  s.seed = 11;
  const NoiseThresholdResult r = noiseOnlyThreshold(s);
  const double rn = double(s.realisations) * s.sizePix * s.sizePix;
  const boost::math::normal unit;
  const double lo = boost::math::quantile(unit, std::pow(0.005, 1.0 / rn));
  const double hi = boost::math::quantile(unit, std::pow(0.995, 1.0 / rn));
  EXPECT_GE(r.noiseOnlyThresholdSigma, lo);
  EXPECT_LE(r.noiseOnlyThresholdSigma, hi + s.stepSigma);
  EXPECT_FALSE(r.atLowestRung);
  // Below the threshold some realisation has an object, at and above none has.
  for (std::size_t k = 0; k < r.thresholdsSigma.size(); ++k) {
    if (r.thresholdsSigma[k] >= r.noiseOnlyThresholdSigma) {
      EXPECT_EQ(r.realisationsWithObjects[k], 0) << r.thresholdsSigma[k];
    }
  }
  // The expected number of pixels above t in one image is N (1 - Phi(t)): at 3 sigma, 5.53.
  const std::size_t at3 = std::size_t(std::lround((3.0 - s.loSigma) / s.stepSigma));
  const double expected3 = s.sizePix * s.sizePix * (1.0 - boost::math::cdf(unit, 3.0));
  EXPECT_NEAR(r.meanObjects[at3], expected3, 4.0 * std::sqrt(expected3 / s.realisations));
}

TEST(NoiseThreshold, ALargerMinimumAreaAndTheFilterLowerIt) {
  NoiseThresholdSettings s;
  s.sizePix = 64;
  s.realisations = 20;
  s.minAreaPix = 1;
  s.loSigma = 1.0;
  s.hiSigma = 7.0;
  s.stepSigma = 0.02;
  const double area1 = noiseOnlyThreshold(s).noiseOnlyThresholdSigma;
  s.minAreaPix = 5;
  const double area5 = noiseOnlyThreshold(s).noiseOnlyThresholdSigma;
  EXPECT_LT(area5, area1);
  // A normalised 3x3 box filter divides the noise sigma by 3.
  ConvKernel box;
  box.width = box.height = 3;
  box.coefficients.assign(9, 1.0f / 9.0f);
  s.filter = box;
  EXPECT_LT(noiseOnlyThreshold(s).noiseOnlyThresholdSigma, area5);
}

TEST(NoiseThreshold, SettingsOutOfRangeAreRefused) {
  NoiseThresholdSettings s;
  s.realisations = 0;
  EXPECT_THROW(noiseOnlyThreshold(s), ConfigError);
  s = NoiseThresholdSettings();
  s.hiSigma = s.loSigma;
  EXPECT_THROW(noiseOnlyThreshold(s), ConfigError);
}

}  // namespace
}  // namespace octarc
