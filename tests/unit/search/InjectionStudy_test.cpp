// The completeness curve of `octarc inject` on hand-made inputs: four injected systems, the
// plain image's and the injected image's spurious scores, known areas; every count, density and
// Wilson bound below is worked out by hand.
#include "octarc/search/InjectionStudy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace octarc {
namespace {

const double kNotFound = std::nan("");

// A: theta_E 1.6", arc mag 21.5, best arc score 0.9 (bins 0, 0)
// B: 2.2", 22.5, 0.5 (bins 1, 1)
// C: 3.0", 23.5, not found (bins 2, 2)
// D: 2.5", 23.0, 0.2 (a bin's lower edge belongs to it: bins 2, 2)
std::vector<InjectedSystemScore> fourSystems() {
  return {{1.6, 21.5, 0.9}, {2.2, 22.5, 0.5}, {3.0, 23.5, kNotFound}, {2.5, 23.0, 0.2}};
}

TEST(InjectionStudy, BinsTakeTheirLowerEdge) {
  EXPECT_EQ(studyBin(1.99, kThetaEBinEdgesArcsec), 0);
  EXPECT_EQ(studyBin(2.0, kThetaEBinEdgesArcsec), 1);
  EXPECT_EQ(studyBin(2.5, kThetaEBinEdgesArcsec), 2);
  EXPECT_EQ(studyBin(21.9, kArcMagBinEdges), 0);
  EXPECT_EQ(studyBin(23.0, kArcMagBinEdges), 2);
}

TEST(InjectionStudy, CurveAtEveryDistinctScore) {
  // Plain image: 3 spurious candidates in 0.01 deg2 (100 per deg2 each); injected image: 2
  // that are no injected arc in 0.02 deg2 (50 per deg2 each). D's 0.2 is also a spurious score:
  // one threshold.
  const std::vector<CompletenessPoint> curve =
      completenessCurve(fourSystems(), {0.7, 0.2, 0.1}, 0.01, {0.5, 0.05}, 0.02);
  ASSERT_EQ(curve.size(), 6u);
  const std::vector<double> thresholds = {0.9, 0.7, 0.5, 0.2, 0.1, 0.05};
  const std::vector<std::int64_t> spurious = {0, 1, 1, 2, 3, 3};
  const std::vector<std::int64_t> injectedSpurious = {0, 0, 1, 1, 1, 2};
  const std::vector<std::int64_t> found = {1, 1, 2, 3, 3, 3};
  for (std::size_t i = 0; i < curve.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(curve[i].scoreMin, thresholds[i]);
    EXPECT_EQ(curve[i].spurious, spurious[i]);
    EXPECT_NEAR(curve[i].spuriousPerDeg2, 100.0 * double(spurious[i]), 1e-9);
    EXPECT_EQ(curve[i].spuriousInjected, injectedSpurious[i]);
    EXPECT_NEAR(curve[i].spuriousInjectedPerDeg2, 50.0 * double(injectedSpurious[i]), 1e-9);
    EXPECT_EQ(curve[i].all.found, found[i]);
    EXPECT_EQ(curve[i].all.injected, 4);
    EXPECT_DOUBLE_EQ(curve[i].all.completeness, double(found[i]) / 4.0);
  }
  // 1 of 4 at z = 1: centre (0.25 + 0.125) / 1.25 = 0.3, half sqrt(0.046875 + 0.015625) / 1.25
  // = 0.2; 3 of 4 mirrors it; 2 of 4: centre 0.5, half sqrt(0.078125) / 1.25 = 0.223607.
  EXPECT_NEAR(curve[0].all.interval.low, 0.1, 1e-12);
  EXPECT_NEAR(curve[0].all.interval.high, 0.5, 1e-12);
  EXPECT_NEAR(curve[2].all.interval.low, 0.276393, 1e-6);
  EXPECT_NEAR(curve[2].all.interval.high, 0.723607, 1e-6);
  EXPECT_NEAR(curve[3].all.interval.low, 0.5, 1e-12);
  EXPECT_NEAR(curve[3].all.interval.high, 0.9, 1e-12);
}

TEST(InjectionStudy, CurvePerBin) {
  const std::vector<CompletenessPoint> curve =
      completenessCurve(fourSystems(), {0.7, 0.2, 0.1}, 0.01, {0.5, 0.05}, 0.02);
  // At LENS_SCORE >= 0.9 only A (bins 0) is found; at >= 0.2 A, B and D.
  const CompletenessPoint& top = curve[0];
  const CompletenessPoint& low = curve[3];
  const std::array<std::int64_t, 3> injected = {1, 1, 2};
  const std::array<std::int64_t, 3> foundTop = {1, 0, 0}, foundLow = {1, 1, 1};
  for (int b = 0; b < kStudyBins; ++b) {
    SCOPED_TRACE(b);
    EXPECT_EQ(top.thetaE[b].injected, injected[b]);
    EXPECT_EQ(top.arcMag[b].injected, injected[b]);
    EXPECT_EQ(top.thetaE[b].found, foundTop[b]);
    EXPECT_EQ(top.arcMag[b].found, foundTop[b]);
    EXPECT_EQ(low.thetaE[b].found, foundLow[b]);
    EXPECT_EQ(low.arcMag[b].found, foundLow[b]);
  }
  // 1 of 2 at z = 1: centre 0.5, half sqrt(0.125 + 0.0625) / 1.5 = 0.288675.
  EXPECT_DOUBLE_EQ(low.thetaE[2].completeness, 0.5);
  EXPECT_NEAR(low.thetaE[2].interval.low, 0.5 - 0.288675, 1e-6);
  EXPECT_NEAR(low.thetaE[2].interval.high, 0.5 + 0.288675, 1e-6);
  // 0 of 1: centre 0.5 / 2, half sqrt(0.25) / 2: [0, 0.5].
  EXPECT_NEAR(top.thetaE[1].interval.high, 0.5, 1e-12);
}

TEST(InjectionStudy, ReadAtSpuriousDensities) {
  const std::vector<CompletenessPoint> curve =
      completenessCurve(fourSystems(), {0.7, 0.2, 0.1}, 0.01, {0.5, 0.05}, 0.02);
  // The lowest threshold whose plain-image density stays at most at the level.
  EXPECT_EQ(pointAtSpuriousDensity(curve, 50.0)->scoreMin, 0.9);
  EXPECT_EQ(pointAtSpuriousDensity(curve, 100.0)->scoreMin, 0.5);
  EXPECT_EQ(pointAtSpuriousDensity(curve, 250.0)->all.found, 3);
  EXPECT_EQ(pointAtSpuriousDensity(curve, 1000.0)->scoreMin, 0.05);
  // Exactly at the level counts, though 9 / 0.018 deg2 divides to a hair above 500 per deg2.
  const std::vector<CompletenessPoint> atLevel =
      completenessCurve({}, {0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1}, 0.018, {}, 0.018);
  ASSERT_GT(9 / 0.018, 500.0);
  EXPECT_EQ(pointAtSpuriousDensity(atLevel, 500.0)->spurious, 9);
  EXPECT_EQ(pointAtSpuriousDensity(atLevel, 450.0)->spurious, 8);
  // A first candidate that is already spurious: no threshold keeps 50 per deg2.
  const std::vector<CompletenessPoint> worse = completenessCurve({}, {0.3}, 0.01, {}, 0.01);
  ASSERT_EQ(worse.size(), 1u);
  EXPECT_FALSE(pointAtSpuriousDensity(worse, 50.0).has_value());
  // No system: nothing to find, and completeness says so.
  EXPECT_EQ(worse[0].all.injected, 0);
  EXPECT_TRUE(std::isnan(worse[0].all.completeness));
}

TEST(InjectionStudy, NoAreaNoDensity) {
  const std::vector<CompletenessPoint> curve =
      completenessCurve(fourSystems(), {0.7}, 0.0, {}, 0.0);
  ASSERT_EQ(curve.size(), 4u);  // 0.9, 0.7, 0.5, 0.2
  EXPECT_TRUE(std::isnan(curve[1].spuriousPerDeg2));
  EXPECT_EQ(curve[1].spurious, 1);
}

}  // namespace
}  // namespace octarc
