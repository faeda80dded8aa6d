// The dark-lens pair criterion's geometry and colour match, on hand-placed points.
#include "octarc/search/DarkLens.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace octarc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(DarkLens, CounterImageInsideTheCircleOnTheFarSide) {
  const CircleFit circle{0.0, 0.0, 10.0};
  // The arc at +x, 9 px from the centre (inside its ridge).
  EXPECT_TRUE(counterImagePlace(circle, 9, 0, -5, 0));  // opposite, 5 px
  EXPECT_TRUE(counterImagePlace(circle, 9, 0, -5, 5));  // 135 degrees, 7.1 px
  EXPECT_TRUE(counterImagePlace(circle, 9, 0, 6 * std::cos(125 * kDeg), 6 * std::sin(125 * kDeg)));
  EXPECT_FALSE(counterImagePlace(circle, 9, 0, 6 * std::cos(115 * kDeg), 6 * std::sin(115 * kDeg)));
  EXPECT_FALSE(counterImagePlace(circle, 9, 0, -2, 5));   // 111.8 degrees
  EXPECT_FALSE(counterImagePlace(circle, 9, 0, -12, 0));  // outside the circle
  EXPECT_FALSE(counterImagePlace(circle, 9, 0, 0, 0));    // at the centre: no side
  EXPECT_FALSE(counterImagePlace(circle, 9, 0, 5, 0));    // the arc's own side

  // Another centre: the arc above it, a counter-image 10 px below, one at 90 degrees.
  const CircleFit shifted{100.0, 50.0, 20.0};
  EXPECT_TRUE(counterImagePlace(shifted, 100, 70, 100, 40));
  EXPECT_FALSE(counterImagePlace(shifted, 100, 70, 110, 50));
}

TEST(DarkLens, SameColourWithinSigmasAndFloor) {
  const ColourMatch match{2.0, 0.1};
  // Errors 0.03 and 0.04: 0.05 combined; tolerance hypot(2 * 0.05, 0.1) = 0.1414.
  EXPECT_TRUE(sameColour({0.50, 0.03}, {0.64, 0.04}, match));
  EXPECT_FALSE(sameColour({0.50, 0.03}, {0.65, 0.04}, match));
  EXPECT_FALSE(sameColour({0.50, 0.03}, {0.20, 0.04}, match));
  // No floor: 2 sigma = 0.1.
  const ColourMatch strict{2.0, 0.0};
  EXPECT_TRUE(sameColour({0.50, 0.03}, {0.59, 0.04}, strict));
  EXPECT_FALSE(sameColour({0.50, 0.03}, {0.61, 0.04}, strict));
  EXPECT_FALSE(sameColour({NAN, 0.03}, {0.5, 0.04}, match));
  EXPECT_FALSE(sameColour({0.5, 0.03}, {0.5, NAN}, match));
}

TEST(DarkLens, NoObjectWithinHalfTheRadiusOfTheCentre) {
  const CircleFit circle{10.0, 20.0, 10.0};
  EXPECT_TRUE(lensFreeCentre(circle, {}));
  EXPECT_TRUE(lensFreeCentre(circle, {{16, 20, 0}}));                // 6 px
  EXPECT_TRUE(lensFreeCentre(circle, {{14, 23, 0}}));                // 5 px: not within
  EXPECT_FALSE(lensFreeCentre(circle, {{16, 20, 0}, {13, 23, 1}}));  // 4.24 px
}

}  // namespace
}  // namespace octarc
