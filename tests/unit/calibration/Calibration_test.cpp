// The calibration studies on cases with known answers: lensing fractions of a hand-made systems
// table, normalised histograms, and the noise-only threshold against the distribution of the
// largest of R N standard normal values (no filter, DETECT_MINAREA 1).
#include "octarc/calibration/Calibration.h"

#include <gtest/gtest.h>

#include <array>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <numeric>
#include <vector>

#include "octarc/calibration/LensingFraction.h"
#include "octarc/calibration/NoiseThreshold.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

ColumnSpec column(const char* name) {
  ColumnSpec c;
  c.name = name;
  c.type = ColumnType::Float64;
  return c;
}

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
  EXPECT_EQ(f.arcSystems, 8);
  ASSERT_EQ(f.rows.size(), 6u);
  const std::int64_t expected[6] = {2, 1, 3, 2, 1, 1};  // per bin: all, distorted and bright
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(f.rows[i].systems, expected[i]) << i;
    const double p = expected[i] / 8.0;
    EXPECT_DOUBLE_EQ(f.rows[i].fraction, p);
    EXPECT_DOUBLE_EQ(f.rows[i].fractionSigma, std::sqrt(p * (1 - p) / 8.0));
  }
  EXPECT_EQ(f.rows[4].arcnessLo, 0.15);
  EXPECT_TRUE(std::isinf(f.rows[4].arcnessHi));
  EXPECT_TRUE(f.rows[5].distortedAndBright);
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
