#include "octarc/simulation/GalaxyCutout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "octarc/core/Error.h"
#include "octarc/detection/MultiThresholdDetector.h"

namespace octarc::simulation {
namespace {

// A background-subtracted image: circular Gaussians of peak amplitude `peak` and width `sigma`
// pixels, centred on integer pixels.
struct Blob {
  int x, y;
  double peak, sigmaPix;
};

ImageF blobImage(int width, int height, const std::vector<Blob>& blobs) {
  ImageF img(width, height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double v = 0.0;
      for (const Blob& b : blobs) {
        const double r2 = double((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y));
        v += b.peak * std::exp(-0.5 * r2 / (b.sigmaPix * b.sigmaPix));
      }
      img(x, y) = float(v);
    }
  return img;
}

std::vector<Segment> detect(const ImageF& img, double thresholdAdu, int minArea = 1) {
  DetectionSettings s;
  s.thresholdsAdu = {thresholdAdu};
  s.minArea = minArea;
  std::vector<Segment> all;
  detectMultiThreshold(img, s, [&](std::vector<Segment>& objs) {
    for (Segment& o : objs) all.push_back(std::move(o));
  });
  return all;
}

// The object whose footprint holds pixel (x, y).
const Segment& objectAt(const std::vector<Segment>& objs, const ImageF& img, int x, int y) {
  const std::int64_t p = img.index(x, y);
  for (const Segment& o : objs)
    for (std::int64_t q : o.pixels)
      if (q == p) return o;
  throw std::runtime_error("no object at the pixel");
}

double stampSum(const ImageF& s) {
  double sum = 0.0;
  for (float v : s.pixels()) sum += v;
  return sum;
}

constexpr double kThreshold = 4.0;  // 4 sigma for sigma = 1

// Galaxy A (peak 100, sigma 2 px) with a fainter neighbour B 10 px to its right: at 4 ADU their
// footprints are disjoint (A reaches 5 px, B starts 3 px left of its centre).
const std::vector<Blob> kPair = {{40, 30, 100.0, 2.0}, {50, 30, 50.0, 1.5}};

TEST(GalaxyCutout, StampHoldsTheObjectFluxAboveTheThresholdAndNothingElse) {
  const ImageF img = blobImage(90, 60, kPair);
  const auto objs = detect(img, kThreshold);
  ASSERT_EQ(objs.size(), 2u);
  const Segment& a = objectAt(objs, img, 40, 30);
  CutoutSettings settings;
  settings.marginPixels = 8;  // wide enough that B's centre falls inside A's stamp
  const GalaxyCutout c = cutGalaxy(img, a, {}, settings);
  ASSERT_EQ(c.verdict, CutoutVerdict::Kept);

  // Independent expectation: every pixel above the threshold left of the gap between the
  // footprints (A reaches x = 45, B starts at x = 47).
  double expected = 0.0;
  std::int64_t area = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x <= 45; ++x)
      if (img(x, y) > float(kThreshold)) {
        expected += img(x, y);
        ++area;
      }
  for (int y = 0; y < img.height(); ++y) EXPECT_LE(img(46, y), float(kThreshold));
  EXPECT_EQ(c.areaPixels, area);
  // A alone has 81 pixels with r^2 < 2 sigma^2 ln(25) = 25.75 (r < 5.07 px); B's wing lifts a
  // few more on its side above 4 ADU.
  EXPECT_GE(area, 81);
  EXPECT_LE(area, 85);
  EXPECT_NEAR(c.fluxAdu, expected, 1e-9 * expected);
  EXPECT_NEAR(stampSum(c.stamp), expected, 1e-9 * expected);

  // Centred on A's peak, odd sizes: the footprint spans 5 px each side, plus the margin.
  EXPECT_NEAR(c.xCentroidPix, 40.0, 0.05);  // B's wing pulls it slightly to the right
  EXPECT_NEAR(c.yCentroidPix, 30.0, 1e-9);  // symmetric in y
  EXPECT_EQ(c.stamp.width(), 2 * (5 + 8) + 1);
  EXPECT_EQ(c.stamp.height(), 2 * (5 + 8) + 1);
  EXPECT_EQ(c.originX, 40 - 13);
  EXPECT_EQ(c.originY, 30 - 13);
  EXPECT_FLOAT_EQ(c.stamp(13, 13), 100.0f);

  // Clean: the neighbour's peak (50, 30) lies inside the stamp but is zero there.
  ASSERT_LT(50 - c.originX, c.stamp.width());
  EXPECT_GT(img(50, 30), 49.0f);
  EXPECT_EQ(c.stamp(50 - c.originX, 30 - c.originY), 0.0f);
  // Noise-free: a pixel of A below the threshold (r = 6 px: 100 e^-4.5 = 1.1 ADU) is zero.
  EXPECT_GT(img(34, 30), 1.0f);
  EXPECT_EQ(c.stamp(34 - c.originX, 30 - c.originY), 0.0f);
  // Inside the footprint the pixel values are kept as they are.
  EXPECT_EQ(c.stamp(42 - c.originX, 31 - c.originY), img(42, 31));
}

TEST(GalaxyCutout, SkipsBorderSmallSaturatedObjects) {
  // C sits on the left edge (x = 1: its footprint reaches x = 0).
  const ImageF img = blobImage(90, 60, {{40, 30, 100.0, 2.0}, {1, 30, 100.0, 2.0}});
  const auto objs = detect(img, kThreshold);
  ASSERT_EQ(objs.size(), 2u);
  const Segment& a = objectAt(objs, img, 40, 30);
  const Segment& c = objectAt(objs, img, 1, 30);
  CutoutSettings settings;
  EXPECT_EQ(cutGalaxy(img, c, {}, settings).verdict, CutoutVerdict::TouchesBorder);
  EXPECT_TRUE(cutGalaxy(img, c, {}, settings).stamp.empty());

  settings.minAreaPixels = 82;  // A has 81 pixels
  EXPECT_EQ(cutGalaxy(img, a, {}, settings).verdict, CutoutVerdict::TooSmall);
  settings.minAreaPixels = 81;
  EXPECT_EQ(cutGalaxy(img, a, {}, settings).verdict, CutoutVerdict::Kept);

  // One saturated pixel in the footprint is enough; one elsewhere does not matter.
  const std::vector<std::int64_t> saturated = {img.index(5, 5), img.index(41, 30)};
  EXPECT_EQ(cutGalaxy(img, a, saturated, settings).verdict, CutoutVerdict::Saturated);
  EXPECT_EQ(cutGalaxy(img, a, {img.index(5, 5)}, settings).verdict, CutoutVerdict::Kept);
}

TEST(GalaxyCutout, SkipsObjectsTruncatedByBlankPixels) {
  ImageF img = blobImage(90, 60, {{40, 30, 100.0, 2.0}});
  // A blank column two pixels beyond A's footprint (x = 35..45) leaves it whole ...
  for (int y = 0; y < 60; ++y) img(47, y) = NAN;
  auto objs = detect(img, kThreshold);
  ASSERT_EQ(objs.size(), 1u);
  EXPECT_EQ(cutGalaxy(img, objs[0], {}, CutoutSettings{}).verdict, CutoutVerdict::Kept);
  // ... one right next to it cuts it.
  for (int y = 0; y < 60; ++y) img(46, y) = NAN;
  objs = detect(img, kThreshold);
  ASSERT_EQ(objs.size(), 1u);
  EXPECT_EQ(cutGalaxy(img, objs[0], {}, CutoutSettings{}).verdict, CutoutVerdict::TouchesBorder);
}

TEST(GalaxyCutout, RejectsBadSettings) {
  const ImageF img = blobImage(30, 30, {{15, 15, 100.0, 2.0}});
  const auto objs = detect(img, kThreshold);
  ASSERT_EQ(objs.size(), 1u);
  CutoutSettings bad;
  bad.minAreaPixels = 0;
  EXPECT_THROW(cutGalaxy(img, objs[0], {}, bad), ConfigError);
  bad.minAreaPixels = 1;
  bad.marginPixels = -1;
  EXPECT_THROW(cutGalaxy(img, objs[0], {}, bad), ConfigError);
  Segment outside;
  outside.number = 1;
  outside.pixels = {30 * 30};
  EXPECT_THROW(cutGalaxy(img, outside, {}, CutoutSettings{}), ConfigError);
}

}  // namespace
}  // namespace octarc::simulation
