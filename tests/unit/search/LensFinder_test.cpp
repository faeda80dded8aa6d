#include "octarc/search/LensFinder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "octarc/measure/MomentsMath.h"

namespace octarc {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(FitCircle, PointsOnACircleGiveItExactly) {
  std::vector<double> x, y, w;
  for (int i = 0; i < 40; ++i) {
    const double t = 0.3 + 1.1 * i / 39.0;  // a 63-degree arc
    x.push_back(1003.0 + 10.0 * std::cos(t));
    y.push_back(-2.0 + 10.0 * std::sin(t));
    w.push_back(1.0 + (i % 7));
  }
  const auto fit = fitCircle(x, y, w);
  ASSERT_TRUE(fit.has_value());
  EXPECT_NEAR(fit->xCentre, 1003.0, 1e-8);
  EXPECT_NEAR(fit->yCentre, -2.0, 1e-8);
  EXPECT_NEAR(fit->radius, 10.0, 1e-8);
}

TEST(FitCircle, LinesAndTooFewPointsHaveNoCircle) {
  EXPECT_FALSE(fitCircle({0, 1, 2, 3}, {0, 2, 4, 6}, {1, 1, 1, 1}).has_value());
  EXPECT_FALSE(fitCircle({0, 1}, {0, 2}, {1, 1}).has_value());
  // Points with no weight do not count.
  EXPECT_FALSE(fitCircle({0, 1, 5}, {0, 2, 1}, {1, 1, 0}).has_value());
}

// A thick arc of radius R around a lens at (lx, ly), spanning +-35 degrees about the direction
// `towardsArcRad` from the lens: its pixels with a flux that peaks along the ridge.
struct SyntheticArc {
  std::vector<double> x, y, w;
};

SyntheticArc makeArc(double lx, double ly, double radiusPix, double towardsArcRad) {
  SyntheticArc arc;
  for (int iy = -200; iy <= 200; ++iy) {
    for (int ix = -200; ix <= 200; ++ix) {
      const double r = std::hypot(double(ix), double(iy));
      const double angle =
          std::remainder(std::atan2(double(iy), double(ix)) - towardsArcRad, 2.0 * kPi);
      if (std::fabs(r - radiusPix) > 1.5 || std::fabs(angle) > 35.0 * kPi / 180.0) continue;
      arc.x.push_back(lx + ix);
      arc.y.push_back(ly + iy);
      arc.w.push_back(std::exp(-0.5 * std::pow(r - radiusPix, 2)));
    }
  }
  return arc;
}

// Arcs at several orientations around a lens of known position and radius: the octopole frame
// (THETA, ARC_SIDE from the measurement core) points to the lens, the circle fit finds its
// centre, and among decoys the lens is chosen with theta_E the arc-lens distance.
TEST(FindLens, SyntheticArcsFindTheirLensAndEinsteinRadius) {
  const double lx = 120.0;
  const double ly = 80.0;
  const double radiusPix = 25.0;
  for (const double towardsDeg : {0.0, 37.0, 90.0, 161.0, 200.0, 290.0}) {
    SCOPED_TRACE(towardsDeg);
    const double towards = towardsDeg * kPi / 180.0;
    const SyntheticArc arc = makeArc(lx, ly, radiusPix, towards);
    const CentralMoments m = centralMoments(arc.x, arc.y, arc.w);
    const OctopoleStats stats = octopoleStats(m);
    ASSERT_TRUE(stats.valid);
    ArcGeometry geometry{m.xMean, m.yMean, stats.thetaRad, stats.arcSide,
                         fitCircle(arc.x, arc.y, arc.w)};
    ASSERT_TRUE(geometry.curvature.has_value());
    // Within a pixel: the ridge is sampled by whole pixels, 3 across (the algebraic start alone
    // is 5 pixels short of R at some of these angles).
    EXPECT_NEAR(geometry.curvature->xCentre, lx, 1.0);
    EXPECT_NEAR(geometry.curvature->yCentre, ly, 1.0);
    EXPECT_NEAR(geometry.curvature->radius, radiusPix, 1.0);
    // Decoys: the arc's own row, a galaxy as far away on the convex side, one on the concave
    // side but off the centre of curvature, one beyond the search radius.
    const double ux = std::cos(towards);
    const double uy = std::sin(towards);
    const std::vector<LensCandidateGalaxy> galaxies = {
        {m.xMean, m.yMean, 0},
        {m.xMean + radiusPix * ux, m.yMean + radiusPix * uy, 1},
        {lx + 12.0 * uy, ly - 12.0 * ux, 2},
        {lx + 0.7, ly - 0.4, 3},  // the lens
        {lx - 200.0 * ux, ly - 200.0 * uy, 4},
    };
    const auto match = findLens(geometry, galaxies, 60.0);
    ASSERT_TRUE(match.has_value());
    EXPECT_EQ(match->row, 3U);
    EXPECT_NEAR(match->einsteinRadiusPix, std::hypot(m.xMean - lx - 0.7, m.yMean - ly + 0.4), 1e-9);
    // The arc centroid sits inside the ridge (the chord pulls it in): theta_E close to R.
    EXPECT_NEAR(match->einsteinRadiusPix, radiusPix, 0.1 * radiusPix);

    // No galaxy on the concave side: a possible dark lens.
    const std::vector<LensCandidateGalaxy> convexOnly = {galaxies[1], galaxies[4]};
    EXPECT_FALSE(findLens(geometry, convexOnly, 60.0).has_value());
  }
}

TEST(FindLens, WithoutACircleTheNearestConcaveGalaxyWins) {
  // An arc along +x (theta = 0) bending towards +y (ARC_SIDE = +1).
  const ArcGeometry arc{10.0, 10.0, 0.0, +1, std::nullopt};
  const std::vector<LensCandidateGalaxy> galaxies = {
      {10.0, 5.0, 0},   // convex side, nearer
      {10.0, 18.0, 1},  // concave
      {13.0, 14.0, 2},  // concave, nearest (distance 5)
  };
  const auto match = findLens(arc, galaxies, 30.0);
  ASSERT_TRUE(match.has_value());
  EXPECT_EQ(match->row, 2U);
  EXPECT_DOUBLE_EQ(match->einsteinRadiusPix, 5.0);
  EXPECT_FALSE(findLens(ArcGeometry{10.0, 10.0, 0.0, 0, std::nullopt}, galaxies, 30.0));
  EXPECT_FALSE(findLens(arc, galaxies, 4.0));
}

// The brightest peak wins over a nearer galaxy; among equal peaks the one nearest the centre of
// curvature; the convex side is out when the side is known, in when it is not.
TEST(FindBrightestLens, BrightestPeakThenNearestToTheCentre) {
  // An arc along +x (theta = 0) bending towards +y (ARC_SIDE = +1), circle centred at (10, 20).
  ArcGeometry arc{10.0, 10.0, 0.0, +1, CircleFit{10.0, 20.0, 10.0}};
  std::vector<LensCandidateGalaxy> galaxies = {
      {10.0, 14.0, 0, 9, 100.0},   // concave, near the arc, fainter peak
      {10.0, 21.0, 1, 12, 50.0},   // concave, near the centre, brightest level
      {12.0, 19.0, 2, 12, 80.0},   // concave, same level, brighter pixel
      {10.0, 2.0, 3, 15, 900.0},   // convex: out while the side is known
      {10.0, 40.0, 4, 15, 900.0},  // beyond the search radius
  };
  auto match = findBrightestLens(arc, galaxies, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 2U);
  EXPECT_DOUBLE_EQ(match->einsteinRadiusPix, std::hypot(2.0, 9.0));
  // Equal peaks: the one nearest the centre of curvature, not the arc.
  galaxies[2].peakFlux = 50.0;
  match = findBrightestLens(arc, galaxies, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 1U);
  // A known FLUX_MAX beats an unknown one at the same level.
  galaxies[1].peakFlux = std::numeric_limits<double>::quiet_NaN();
  match = findBrightestLens(arc, galaxies, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 2U);
  // Side unknown: any side, so the convex galaxy's brighter peak wins.
  arc.arcSide = 0;
  match = findBrightestLens(arc, galaxies, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 3U);
  // Only the convex and the distant galaxies with the side known: none.
  arc.arcSide = +1;
  EXPECT_FALSE(findBrightestLens(arc, {galaxies[3], galaxies[4]}, 25.0));
}

TEST(FindBrightestLens, ThePeakOfABlendCountsAtAnyDistanceOnTheConcaveSide) {
  ArcGeometry arc{10.0, 10.0, 0.0, +1, std::nullopt};
  LensCandidateGalaxy core{10.1, 10.2, 7, 15, 500.0};  // concave side (+y), 0.22 px off
  core.inArc = true;
  const std::vector<LensCandidateGalaxy> galaxies = {{10.0, 15.0, 1, 11, 100.0}, core};
  auto match = findBrightestLens(arc, galaxies, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 7U);
  EXPECT_NEAR(match->einsteinRadiusPix, std::hypot(0.1, 0.2), 1e-12);
  // Not marked as the arc's own: at the centroid (the arc itself), so left out.
  LensCandidateGalaxy plain = core;
  plain.inArc = false;
  match = findBrightestLens(arc, {galaxies[0], plain}, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 1U);
  // On the convex side it is the arc's own ridge: out, unless the side is unknown.
  LensCandidateGalaxy ridge = core;
  ridge.y = 9.8;
  match = findBrightestLens(arc, {galaxies[0], ridge}, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 1U);
  arc.arcSide = 0;
  match = findBrightestLens(arc, {galaxies[0], ridge}, 25.0);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->row, 7U);
}

// An SIS double: images at theta_E + beta and theta_E - beta on opposite sides of the lens.
TEST(EstimateEinsteinRadius, ADoubleGivesThetaEExactly) {
  const double lx = 50.0, ly = 40.0, thetaE = 12.0, beta = 4.0;
  const double towards = 30.0 * kPi / 180.0;
  const double ax = lx + (thetaE + beta) * std::cos(towards);
  const double ay = ly + (thetaE + beta) * std::sin(towards);
  auto at = [&](double distance, double angleDeg, std::size_t row) {
    const double a = towards + angleDeg * kPi / 180.0;
    return LensCandidateGalaxy{lx + distance * std::cos(a), ly + distance * std::sin(a), row};
  };
  const std::vector<LensCandidateGalaxy> others = {
      at(5.0, 90.0, 10),                   // off to the side: not a counter-image
      at(0.2, 180.0, 11),                  // the lens's own core
      at(thetaE + beta + 1.0, 180.0, 12),  // farther than the arc
      at(thetaE - beta, 155.0, 13),        // opposite, but less so than the next
      at(thetaE - beta, 180.0, 14),        // the counter-image
  };
  const EinsteinRadiusEstimate e = estimateEinsteinRadius(lx, ly, ax, ay, std::nullopt, others);
  EXPECT_EQ(e.method, ThetaEMethod::kCounterImage);
  ASSERT_TRUE(e.counterImage);
  EXPECT_EQ(*e.counterImage, 4U);
  EXPECT_NEAR(e.thetaEPix, thetaE, 1e-9);
  EXPECT_DOUBLE_EQ(einsteinRadiusFromDouble(thetaE + beta, thetaE - beta), thetaE);
  // Less than kDoubleMinAngleDeg from the arc: no counter-image, the distance estimate.
  const EinsteinRadiusEstimate side =
      estimateEinsteinRadius(lx, ly, ax, ay, std::nullopt, {at(thetaE - beta, 145.0, 15)});
  EXPECT_EQ(side.method, ThetaEMethod::kDistance);
  EXPECT_FALSE(side.counterImage);
}

// Without a counter-image: the arc's circle when it is centred on the lens, else the distance.
TEST(EstimateEinsteinRadius, CurvatureAboutTheLensElseTheDistance) {
  const double lx = 120.0, ly = 80.0, radiusPix = 25.0;
  const SyntheticArc synthetic = makeArc(lx, ly, radiusPix, 0.7);
  const auto circle = fitCircle(synthetic.x, synthetic.y, synthetic.w);
  ASSERT_TRUE(circle);
  // The arc's ridge point on the circle: theta_E is the circle's radius, within the fit's pixel.
  const double ax = lx + radiusPix * std::cos(0.7), ay = ly + radiusPix * std::sin(0.7);
  EinsteinRadiusEstimate e = estimateEinsteinRadius(lx, ly, ax, ay, circle, {});
  EXPECT_EQ(e.method, ThetaEMethod::kCurvature);
  EXPECT_NEAR(e.thetaEPix, radiusPix, 1.0);
  EXPECT_DOUBLE_EQ(e.thetaEPix, circle->radius);
  // A half ring of radius 10 about the lens: its centroid lies at 2 R / pi; theta_E is R.
  e = estimateEinsteinRadius(0.0, 0.0, 20.0 / kPi, 0.0, CircleFit{0.0, 0.0, 10.0}, {});
  EXPECT_EQ(e.method, ThetaEMethod::kCurvature);
  EXPECT_DOUBLE_EQ(e.thetaEPix, 10.0);
  // A circle centred off the lens (by more than kCurvatureCentreFraction R), or much larger
  // than the arc-lens distance, says nothing about it: the distance estimate.
  e = estimateEinsteinRadius(0.0, 0.0, 10.0, 0.0, CircleFit{3.5, 0.0, 10.0}, {});
  EXPECT_EQ(e.method, ThetaEMethod::kDistance);
  e = estimateEinsteinRadius(0.0, 0.0, 10.0, 0.0, CircleFit{0.0, 0.0, 16.5}, {});
  EXPECT_EQ(e.method, ThetaEMethod::kDistance);
  // The outer image of a double whose source lies at the median beta = theta_E / sqrt(2):
  // theta_E exactly.
  const double thetaE = 7.0;
  const double d = thetaE * (1.0 + 1.0 / std::sqrt(2.0));
  e = estimateEinsteinRadius(3.0, 4.0, 3.0 + d * 0.6, 4.0 - d * 0.8, std::nullopt, {});
  EXPECT_EQ(e.method, ThetaEMethod::kDistance);
  EXPECT_NEAR(e.thetaEPix, thetaE, 1e-12);
  EXPECT_FALSE(e.counterImage);
  // An arc on its lens: no estimate.
  e = estimateEinsteinRadius(3.0, 4.0, 3.1, 4.0, std::nullopt, {});
  EXPECT_EQ(e.method, ThetaEMethod::kNone);
  EXPECT_TRUE(std::isnan(e.thetaEPix));
}

}  // namespace
}  // namespace octarc
