#include "octarc/search/LensFinder.h"

#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace octarc
