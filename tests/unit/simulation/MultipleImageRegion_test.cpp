#include "octarc/simulation/MultipleImageRegion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "LensTestSupport.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/LensSystem.h"

namespace octarc::simulation {
namespace {

TEST(MultipleImageRegion, CutOfTheSisIsTheEinsteinCircle) {
  const MultipleImageRegion region({1.3, 0.0, 0.0, 0.0});
  for (const Vec2& p : region.cut()) EXPECT_NEAR(std::hypot(p[0], p[1]), 1.3, 1e-12);
  // The SIS caustic is the single point at the centre.
  for (const Vec2& p : region.tangentialCaustic()) EXPECT_NEAR(std::hypot(p[0], p[1]), 0.0, 1e-12);
  EXPECT_TRUE(region.contains({1.29, 0.0}));
  EXPECT_FALSE(region.contains({0.0, 1.31}));
  EXPECT_THROW(MultipleImageRegion({0.0, 0.1, 0.0, 0.0}), ConfigError);
}

// The cut's extreme points are the deflections along the axes: b sqrt(1 - eps) on the major
// axis, b sqrt(1 + eps) on the minor axis, the latter beyond the Einstein radius b.
TEST(MultipleImageRegion, CutReachesBeyondTheEinsteinRadiusAlongTheMinorAxis) {
  const double b = 1.0, eps = 0.15, pa = 0.4;
  const MultipleImageRegion region({b, eps, 0.0, pa});
  const Vec2 minor{-std::sin(pa), std::cos(pa)};
  const Vec2 major{std::cos(pa), std::sin(pa)};
  const double rMinor = b * std::sqrt(1.0 + eps), rMajor = b * std::sqrt(1.0 - eps);
  EXPECT_TRUE(region.contains({0.999 * rMinor * minor[0], 0.999 * rMinor * minor[1]}));
  EXPECT_FALSE(region.contains({1.001 * rMinor * minor[0], 1.001 * rMinor * minor[1]}));
  EXPECT_TRUE(region.contains({0.999 * rMajor * major[0], 0.999 * rMajor * major[1]}));
  EXPECT_FALSE(region.contains({1.001 * rMajor * major[0], 1.001 * rMajor * major[1]}));
  EXPECT_NEAR(region.boundingRadiusArcsec(), rMinor, 1e-6);
}

// By sampling: every drawn source has at least two images (counted from the lens equation,
// independently of the polygons), every point outside the region has one, and sources beyond
// the Einstein radius are drawn, in the proportion of the area they cover.
TEST(MultipleImageRegion, DrawnSourcesAreMultiplyImagedAndFillTheRegion) {
  for (const double eps : {0.02, 0.09, 0.19}) {
    const EllipticalPotentialParams params{1.4, eps, 0.0, 1.1};
    const EllipticalPotentialLens lens(params);
    const MultipleImageRegion region(params);
    std::mt19937_64 rng(11);
    int beyond = 0;
    constexpr int kDraws = 400;
    for (int i = 0; i < kDraws; ++i) {
      const Vec2 beta = region.drawUniform(rng);
      ASSERT_GE(test::countImagesCoreless(lens, beta), 2)
          << "eps " << eps << " beta " << beta[0] << ", " << beta[1];
      if (std::hypot(beta[0], beta[1]) > params.einsteinRadiusArcsec) ++beyond;
    }
    EXPECT_GT(beyond, 0) << "eps " << eps;
    // Outside the region (but inside the disc) a source has a single image.
    int outside = 0;
    for (int i = 0; i < 4000 && outside < 100; ++i) {
      const Vec2 beta = drawUniformInDisc(1.2 * region.boundingRadiusArcsec(), rng);
      if (region.contains(beta)) continue;
      ++outside;
      EXPECT_EQ(test::countImagesCoreless(lens, beta), 1)
          << "eps " << eps << " beta " << beta[0] << ", " << beta[1];
    }
    EXPECT_EQ(outside, 100);
  }
}

}  // namespace
}  // namespace octarc::simulation
