// The context columns on hand-placed rows: distances, magnitudes and angles worked out by hand.
#include "octarc/selection/ArcContext.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "SelectionTestSupport.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

// A row: position, level, number, parent, flux, size, major-axis angle (deg) and ARC_SIDE.
struct Row {
  double x, y;
  int level, number, parent;
  double flux, size, thetaDeg, side;
};

Table catalogOf(const std::vector<Row>& rows) {
  std::vector<double> x, y, level, number, parent, flux, size, e1, e2, side;
  for (const Row& r : rows) {
    x.push_back(r.x);
    y.push_back(r.y);
    level.push_back(r.level);
    number.push_back(r.number);
    parent.push_back(r.parent);
    flux.push_back(r.flux);
    size.push_back(r.size);
    // e = 0.5 at angle theta: (e1, e2) = e (cos 2 theta, sin 2 theta).
    e1.push_back(0.5 * std::cos(2.0 * r.thetaDeg * M_PI / 180.0));
    e2.push_back(0.5 * std::sin(2.0 * r.thetaDeg * M_PI / 180.0));
    side.push_back(r.side);
  }
  return test::makeTable({{"X_IMAGE", x},
                          {"Y_IMAGE", y},
                          {"THRESH_LEVEL", level},
                          {"NUMBER", number},
                          {"PARENT_NUMBER", parent},
                          {"FLUX_ISO", flux},
                          {"SIZE_IMAGE", size},
                          {"E1_IMAGE", e1},
                          {"E2_IMAGE", e2},
                          {"ARC_SIDE", side}});
}

constexpr double kScale = 0.25;  // arcsec per pixel

TEST(ArcContext, TangentialArcAroundItsLensWithACounterImage) {
  // Lens at (100, 100); arc 20 px to its right, its major axis vertical (tangential), curving
  // round the lens: the +b axis at theta = 90 deg is (-1, 0), towards the lens, so ARC_SIDE = +1.
  // A fainter counter-image 10 px to the lens's left.
  const Table catalog = catalogOf({{100, 100, 1, 1, 0, 1000, 5, 0, 0},
                                   {120, 100, 1, 2, 0, 100, 3, 90, +1},
                                   {90, 100, 1, 3, 0, 50, 2, 90, +1}});
  const std::vector<ArcContext> c = arcContexts(catalog, {kScale, 6.0});
  ASSERT_EQ(c.size(), 3u);
  const ArcContext& arc = c[1];
  EXPECT_DOUBLE_EQ(arc.neighbourDistanceArcsec, 20 * kScale);
  EXPECT_NEAR(arc.neighbourDeltaMag, 2.5, 1e-12);  // a tenth of the flux
  EXPECT_NEAR(arc.neighbourDistanceInSizes, 20.0 / (std::sqrt(2.0) * 5.0), 1e-12);
  EXPECT_NEAR(arc.tangentialAngleDeg, 0.0, 1e-9);
  EXPECT_EQ(arc.concaveSide, 1.0);
  EXPECT_NEAR(arc.counterDistanceRatio, 0.5, 1e-12);
  EXPECT_NEAR(arc.counterDeltaMag, -2.5 * std::log10(0.5), 1e-12);
  // The counter-image's own neighbour is the lens (10 px); the arc on its other side is twice as
  // far, beyond the window of 1.5 neighbour distances: no counter-image.
  EXPECT_DOUBLE_EQ(c[2].neighbourDistanceArcsec, 10 * kScale);
  EXPECT_TRUE(std::isnan(c[2].counterDistanceRatio));
  // Its major axis is tangential too, but its +b axis (-1, 0) points away from the lens: with
  // ARC_SIDE = +1 the lens is on its convex side.
  EXPECT_EQ(c[2].concaveSide, -1.0);
  // The lens has nothing brighter: no context at all.
  EXPECT_TRUE(std::isnan(c[0].neighbourDistanceArcsec));
  EXPECT_TRUE(std::isnan(c[0].tangentialAngleDeg));
  EXPECT_TRUE(std::isnan(c[0].counterDistanceRatio));
}

TEST(ArcContext, AnglesRadialAndDiagonal) {
  // A radial row (major axis pointing at the lens): 90 deg; one at 45 deg to the radius: 45;
  // ARC_SIDE 0: concave side unknown. No counter-image: NaN.
  const Table catalog = catalogOf({{100, 100, 1, 1, 0, 1000, 5, 0, 0},
                                   {100, 140, 1, 2, 0, 10, 3, 90, 0},
                                   {130, 130, 1, 3, 0, 10, 3, 0, 0}});
  const std::vector<ArcContext> c = arcContexts(catalog, {kScale, 20.0});
  EXPECT_NEAR(c[1].tangentialAngleDeg, 90.0, 1e-9);
  EXPECT_NEAR(c[2].tangentialAngleDeg, 45.0, 1e-9);
  EXPECT_EQ(c[1].concaveSide, 0.0);
  // Row 2's counter-image window about the lens holds row 1 at 90 deg only: none.
  EXPECT_TRUE(std::isnan(c[2].counterDistanceRatio));
}

TEST(ArcContext, AncestorsAreNeverTheNeighbourNorAreFarGalaxies) {
  // Level 1: the arc merged with its lens (centroid pulled to (108, 100)). Level 2: the lens and
  // the arc apart. The arc's neighbour is the level-2 lens, not its brighter ancestor.
  const Table catalog = catalogOf({{108, 100, 1, 1, 0, 2000, 8, 0, 0},
                                   {100, 100, 2, 1, 1, 900, 4, 0, 0},
                                   {124, 100, 2, 2, 1, 100, 3, 90, 1}});
  const std::vector<ArcContext> c = arcContexts(catalog, {kScale, 6.0});
  EXPECT_DOUBLE_EQ(c[2].neighbourDistanceArcsec, 24 * kScale);
  // The level-2 lens is inside the level-1 blob too, and brighter rows are only its ancestor:
  // none. With a 1" reach the arc has no neighbour either (6 arcsec = 24 px is the edge).
  EXPECT_TRUE(std::isnan(c[1].neighbourDistanceArcsec));
  const std::vector<ArcContext> near = arcContexts(catalog, {kScale, 1.0});
  EXPECT_TRUE(std::isnan(near[2].neighbourDistanceArcsec));
}

TEST(ArcContext, MissingColumnAndBadScaleAreConfigErrors) {
  const Table catalog = test::makeTable({{"X_IMAGE", {1.0}}, {"Y_IMAGE", {1.0}}});
  test::expectError<ConfigError>([&] { arcContexts(catalog, {kScale, 6.0}); }, {"THRESH_LEVEL"});
  const Table good = catalogOf({{1, 1, 1, 1, 0, 1, 1, 0, 0}});
  test::expectError<ConfigError>([&] { arcContexts(good, {0.0, 6.0}); }, {"pixel scale"});
  EXPECT_EQ(arcContextColumns().size(), contextValues(ArcContext{}).size());
}

}  // namespace
}  // namespace octarc
