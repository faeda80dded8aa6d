// Gathering an object's pixels once for every measurement: coordinates split from linear
// indices (including footprints given out of raster order), values read from the right image.
#include "octarc/measure/ObjectPixels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace octarc {
namespace {

// Pixel (x, y) of a 7 x 5 image holds 10 y + x; the detection image holds -(10 y + x).
struct Images {
  ImageF measured{7, 5, 0.0f}, detected{7, 5, 0.0f}, variance{7, 5, 0.0f};
  Images() {
    for (std::int64_t y = 0; y < 5; ++y) {
      for (std::int64_t x = 0; x < 7; ++x) {
        measured[y * 7 + x] = float(10 * y + x);
        detected[y * 7 + x] = -float(10 * y + x);
        variance[y * 7 + x] = float(100 + 10 * y + x);
      }
    }
  }
};

TEST(ObjectPixels, SplitsIndicesAndReadsBothImages) {
  Images im;
  MeasureContext c;
  c.measurement = &im.measured;
  c.detection = &im.detected;
  c.variance = &im.variance;
  Segment s;
  // Row ends, a row jump and then an earlier row again: each index is split on its own.
  s.pixels = {5, 6, 7, 20, 34, 3};
  ObjectPixels p;
  p.gather(s, c);
  ASSERT_EQ(p.size(), 6u);
  const double xs[] = {5, 6, 0, 6, 6, 3};
  const double ys[] = {0, 0, 1, 2, 4, 0};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(p.x[i], xs[i]) << i;
    EXPECT_EQ(p.y[i], ys[i]) << i;
    EXPECT_EQ(p.value[i], 10 * ys[i] + xs[i]) << i;
    EXPECT_EQ(p.detectionValues()[i], -(10 * ys[i] + xs[i])) << i;
    EXPECT_EQ(p.variance[i], 100 + 10 * ys[i] + xs[i]) << i;
  }
  EXPECT_TRUE(p.valuesFinite);
}

TEST(ObjectPixels, UnfilteredDetectionIsTheMeasurementAndBuffersAreReused) {
  Images im;
  im.measured[8] = std::numeric_limits<float>::quiet_NaN();
  MeasureContext c;
  c.measurement = &im.measured;
  c.detection = &im.measured;
  Segment big;
  big.pixels = {8, 9, 10, 11};
  ObjectPixels p;
  p.gather(big, c);
  EXPECT_FALSE(p.valuesFinite);
  EXPECT_TRUE(p.variance.empty());
  EXPECT_TRUE(std::isnan(p.detectionValues()[0]));
  EXPECT_EQ(p.detectionValues()[1], 12.0);  // (2, 1)
  // A smaller object next: only its own pixels, and the NaN state does not stick.
  Segment small;
  small.pixels = {33};
  p.gather(small, c);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p.x[0], 5.0);
  EXPECT_EQ(p.y[0], 4.0);
  EXPECT_EQ(p.value[0], 45.0);
  EXPECT_TRUE(p.valuesFinite);
}

TEST(ObjectPixels, RunsGiveTheSameArraysAsIndices) {
  Images im;
  im.measured[16] = std::numeric_limits<float>::infinity();
  MeasureContext c;
  c.measurement = &im.measured;
  c.detection = &im.detected;
  c.variance = &im.variance;
  Segment indices;
  indices.pixels = {2, 3, 4, 14, 15, 16, 17, 34};
  Segment runs;
  runs.runs = {{0, 2, 4}, {2, 0, 3}, {4, 6, 6}};
  ObjectPixels a, b;
  a.gather(indices, c);
  b.gather(runs, c);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.detectionValues(), b.detectionValues());
  EXPECT_EQ(a.variance, b.variance);
  ASSERT_EQ(b.size(), 8u);
  EXPECT_EQ(b.value[2], 4.0);
  EXPECT_EQ(b.value[7], 46.0);
  EXPECT_FALSE(a.valuesFinite);
  EXPECT_FALSE(b.valuesFinite);
}

}  // namespace
}  // namespace octarc
