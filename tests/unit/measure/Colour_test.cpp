// Isophotal magnitudes of a band in a given footprint, and colours, worked out by hand.
#include "octarc/measure/Colour.h"

#include <gtest/gtest.h>

#include <cmath>

namespace octarc {
namespace {

// Four footprint pixels holding 10, 20, 30 and 40 ADU (flux 100) in a 10 x 10 image: three on
// row 2 (x 3-5), one on row 3 (x 4). Every other pixel holds 1000, which must not count.
struct Fixture {
  ImageF pixels{10, 10, 1000.0f};
  std::vector<PixelRun> footprint{{2, 3, 5}, {3, 4, 4}};
  Fixture() {
    pixels(3, 2) = 10;
    pixels(4, 2) = 20;
    pixels(5, 2) = 30;
    pixels(4, 3) = 40;
  }
};

TEST(Colour, IsophotalMagnitudeWithTheGlobalNoise) {
  Fixture f;
  BandImage band;
  band.pixels = &f.pixels;
  band.sigmaAdu = 2.0;
  band.magZeropoint = 25.0;
  // 25 - 2.5 log10(100) = 20; error sqrt(4 * 2^2) = 4 ADU, 1.086 * 4 / 100 mag.
  BandMagnitude m = isoMagnitude(band, f.footprint);
  EXPECT_NEAR(m.mag, 20.0, 1e-12);
  EXPECT_NEAR(m.magErr, 0.04344, 1e-12);
  // With a gain of 4 e-/ADU: sqrt(16 + 100 / 4) = sqrt(41).
  band.gain = 4.0;
  m = isoMagnitude(band, f.footprint);
  EXPECT_NEAR(m.magErr, 1.086 * std::sqrt(41.0) / 100.0, 1e-12);
  // A NaN pixel is left out: flux 60, three pixels.
  f.pixels(4, 3) = NAN;
  m = isoMagnitude(band, f.footprint);
  EXPECT_NEAR(m.mag, 25.0 - 2.5 * std::log10(60.0), 1e-12);
  EXPECT_NEAR(m.magErr, 1.086 * std::sqrt(3 * 4.0 + 60.0 / 4.0) / 60.0, 1e-12);
}

TEST(Colour, IsophotalMagnitudeWithAVarianceMap) {
  Fixture f;
  ImageF variance(10, 10, 1e6f);
  variance(3, 2) = 1;
  variance(4, 2) = 2;
  variance(5, 2) = 3;
  variance(4, 3) = 4;
  BandImage band;
  band.pixels = &f.pixels;
  band.variance = &variance;
  band.sigmaAdu = 2.0;
  band.gain = 5.0;
  band.magZeropoint = 30.0;
  // Variances 1 + 2 + 3 + 4 = 10; Poisson sum p/gain * var/sigma^2 = (10 + 40 + 90 + 160) / 20
  // = 15: error 5 ADU.
  const BandMagnitude m = isoMagnitude(band, f.footprint);
  EXPECT_NEAR(m.mag, 25.0, 1e-12);
  EXPECT_NEAR(m.magErr, 1.086 * 5.0 / 100.0, 1e-12);
}

TEST(Colour, NotMeasurableIsNaN) {
  Fixture f;
  BandImage band;
  band.pixels = &f.pixels;
  band.sigmaAdu = 1.0;
  f.pixels(4, 3) = -70;  // flux 10 + 20 + 30 - 70 = -10
  EXPECT_TRUE(std::isnan(isoMagnitude(band, f.footprint).mag));
  EXPECT_TRUE(std::isnan(isoMagnitude(band, {}).mag));  // no pixel
  const Colour c = colourOf(BandMagnitude{21.0, 0.03}, BandMagnitude{20.0, 0.04});
  EXPECT_DOUBLE_EQ(c.value, 1.0);
  EXPECT_NEAR(c.error, 0.05, 1e-15);
  EXPECT_TRUE(std::isnan(colourOf(BandMagnitude{}, BandMagnitude{20.0, 0.04}).value));
}

TEST(Colour, BandNamesForColumnNames) {
  EXPECT_TRUE(isBandName("g"));
  EXPECT_TRUE(isBandName("HSC_i2"));
  EXPECT_TRUE(isBandName("abcdefghijklmnop"));  // 16 characters
  EXPECT_FALSE(isBandName(""));
  EXPECT_FALSE(isBandName("abcdefghijklmnopq"));  // 17
  EXPECT_FALSE(isBandName("g-r"));
  EXPECT_FALSE(isBandName("g r"));
  EXPECT_FALSE(isBandName("g,"));
}

}  // namespace
}  // namespace octarc
