// The Lupton et al. (2004) colour mapping against values computed by hand.
#include "octarc/plot/LuptonColour.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace octarc {
namespace {

void expectRgb(const Rgb8& c, int red, int green, int blue) {
  EXPECT_EQ(int(c.red), red);
  EXPECT_EQ(int(c.green), green);
  EXPECT_EQ(int(c.blue), blue);
}

TEST(LuptonColour, EqualFluxesAreGrey) {
  // I = 0.2, Q I / stretch = 1: each channel 0.2 asinh(1) / 1 = 0.17627, 255 x = 44.95.
  expectRgb(luptonRgb(0.2, 0.2, 0.2, {5.0, 1.0}), 45, 45, 45);
}

TEST(LuptonColour, AsinhOfTheIntensityScalesEveryChannel) {
  // I = 0.2, Q I = 0.4, factor asinh(0.4) / 0.4 = 0.975088: 0.29253, 0.19502, 0.09751 of 255.
  expectRgb(luptonRgb(0.3, 0.2, 0.1, {2.0, 1.0}), 75, 50, 25);
  // The softening in ADU: the same pixel in units 100 times smaller.
  expectRgb(luptonRgb(30.0, 20.0, 10.0, {2.0, 100.0}), 75, 50, 25);
}

TEST(LuptonColour, ClipKeepsTheHue) {
  // I = 20, factor asinh(20) / 20 = 0.184475: 5.534, 3.690, 1.845; all divided by 5.534.
  expectRgb(luptonRgb(30.0, 20.0, 10.0, {1.0, 1.0}), 255, 170, 85);
  // Far brighter: the same hue, not white.
  expectRgb(luptonRgb(3e6, 2e6, 1e6, {1.0, 1.0}), 255, 170, 85);
}

TEST(LuptonColour, NegativeChannelsAreZero) {
  // I = 0.2, factor asinh(0.2) / 0.2 = 0.993451: red 253.3.
  expectRgb(luptonRgb(1.0, 0.0, -0.4, {1.0, 1.0}), 253, 0, 0);
}

TEST(LuptonColour, BlackWithoutLightOrData) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expectRgb(luptonRgb(0.0, 0.0, 0.0, {5.0, 1.0}), 0, 0, 0);
  expectRgb(luptonRgb(-1.0, 0.5, 0.2, {5.0, 1.0}), 0, 0, 0);
  expectRgb(luptonRgb(nan, 1.0, 1.0, {5.0, 1.0}), 0, 0, 0);
  expectRgb(luptonRgb(1.0, 1.0, 1.0, {5.0, 0.0}), 0, 0, 0);
  expectRgb(luptonRgb(1.0, 1.0, 1.0, {0.0, 1.0}), 0, 0, 0);
}

}  // namespace
}  // namespace octarc
