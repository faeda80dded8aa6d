#include "octarc/detection/SegmentationReader.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "DetectionTestUtil.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

using Pixels = std::vector<std::int64_t>;

// Builds an image from rows written top (y = 0) to bottom.
ImageI32 labels(std::int64_t width, const std::vector<std::int32_t>& values) {
  ImageI32 image(width, static_cast<std::int64_t>(values.size()) / width);
  for (std::size_t i = 0; i < values.size(); ++i) image[static_cast<std::int64_t>(i)] = values[i];
  return image;
}

std::string messageOf(const std::vector<ImageI32>& levels, const std::vector<std::string>& names) {
  try {
    segmentsFromLabels(levels, names);
  } catch (const IoError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SegmentationReader, ThreeNestedLevelsWithSparseLabels) {
  // 6 x 3 images. Level 1: objects 4 and 9. Level 2: object 2 inside 4, objects 7 and 8 inside
  // 9. Level 3: object 5 inside 7.
  const std::vector<ImageI32> levels = {labels(6, {4, 4, 0, 9, 9, 9,  //
                                                   4, 4, 0, 9, 9, 9,  //
                                                   0, 0, 0, 9, 9, 9}),
                                        labels(6, {2, 0, 0, 7, 7, 0,  //
                                                   0, 0, 0, 0, 0, 0,  //
                                                   0, 0, 0, 0, 0, 8}),
                                        labels(6, {0, 0, 0, 0, 5, 0,  //
                                                   0, 0, 0, 0, 0, 0,  //
                                                   0, 0, 0, 0, 0, 0})};
  const auto segments = segmentsFromLabels(levels, {"a.fits", "b.fits", "c.fits"});
  ASSERT_EQ(segments.size(), 6u);
  struct Expected {
    std::int32_t number;
    int level;
    std::int32_t parent;
    Pixels pixels;
  };
  const std::vector<Expected> expected = {
      {4, 1, 0, {0, 1, 6, 7}}, {9, 1, 0, {3, 4, 5, 9, 10, 11, 15, 16, 17}},
      {2, 2, 4, {0}},          {7, 2, 9, {3, 4}},
      {8, 2, 9, {17}},         {5, 3, 7, {4}}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(segments[i].number, expected[i].number);
    EXPECT_EQ(segments[i].level, expected[i].level);
    EXPECT_EQ(segments[i].parentNumber, expected[i].parent);
    EXPECT_EQ(segments[i].pixels, expected[i].pixels);
  }
}

TEST(SegmentationReader, EmptyLevelsAndEmptyStack) {
  EXPECT_TRUE(segmentsFromLabels({}, {}).empty());
  const auto segments =
      segmentsFromLabels({labels(2, {1, 0, 0, 0}), labels(2, {0, 0, 0, 0})}, {"a", "b"});
  ASSERT_EQ(segments.size(), 1u);
  EXPECT_EQ(segments[0].pixels, Pixels{0});
}

TEST(SegmentationReader, HugeSparseLabelValues) {
  const auto segments =
      segmentsFromLabels({labels(3, {2000000000, 0, 7, 2000000000, 0, 7})}, {"big.fits"});
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_EQ(segments[0].number, 7);
  EXPECT_EQ(segments[0].pixels, (Pixels{2, 5}));
  EXPECT_EQ(segments[1].number, 2000000000);
  EXPECT_EQ(segments[1].pixels, (Pixels{0, 3}));
}

TEST(SegmentationReader, RejectsSizeMismatchNamingBothSizes) {
  const std::string msg =
      messageOf({labels(2, {1, 0, 0, 0}), labels(3, {0, 0, 0})}, {"low.fits", "high.fits"});
  EXPECT_EQ(msg, "high.fits: segmentation image is 3x1 but low.fits is 2x2");
}

TEST(SegmentationReader, RejectsNegativeLabel) {
  const std::string msg = messageOf({labels(2, {1, 0, 0, -3})}, {"neg.fits"});
  EXPECT_EQ(msg, "neg.fits: negative label -3 at FITS pixel (2, 2) of a segmentation image");
}

TEST(SegmentationReader, RejectsLabelOnLowerBackground) {
  const std::string msg =
      messageOf({labels(3, {1, 1, 0}), labels(3, {0, 5, 5})}, {"t1.fits", "t2.fits"});
  EXPECT_EQ(msg,
            "t2.fits: label 5 at level 2 has FITS pixel (3, 1) on the background of level 1 "
            "(t1.fits); the levels do not nest (give SEGMENTATION_NAME and DETECT_LEVELS lowest "
            "threshold first)");
}

TEST(SegmentationReader, RejectsLabelSpanningTwoLowerLabels) {
  const std::string msg =
      messageOf({labels(3, {1, 1, 2}), labels(3, {0, 5, 5})}, {"t1.fits", "t2.fits"});
  EXPECT_EQ(msg,
            "t2.fits: label 5 at level 2 lies in labels 1 and 2 of level 1 (t1.fits); the levels "
            "do not nest (give SEGMENTATION_NAME and DETECT_LEVELS lowest threshold first)");
  for (const char* ch : {"\n", "\r"}) EXPECT_EQ(msg.find(ch), std::string::npos);
}

TEST(SegmentationReader, RejectsNameCountMismatch) {
  EXPECT_THROW(segmentsFromLabels({labels(1, {0})}, {}), ConfigError);
}

// Real SEGMENTATION images of source-extractor at two thresholds (deblending off, no cleaning,
// no filter) nest, and each label's pixel count is its ISOAREA: check both with a catalog.
TEST(SegmentationReader, ReadsNestedSourceExtractorSegmentations) {
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  const auto dir = test::scratchDir();
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  ImageF image(80, 60);
  for (float& v : image.pixels()) v = noise(rng);
  // Two close Gaussians that merge at the low threshold and separate at the high one.
  for (std::int64_t y = 0; y < 60; ++y) {
    for (std::int64_t x = 0; x < 80; ++x) {
      auto g = [&](double cx, double cy, double peak) {
        return peak * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2.0 * 2.5 * 2.5));
      };
      image(x, y) += static_cast<float>(g(30, 30, 40) + g(39, 31, 30) + g(65, 12, 25));
    }
  }
  test::writeFloatFits(dir / "img.fits", image);
  const std::string common =
      " -FILTER N -DEBLEND_NTHRESH 1 -CLEAN N -BACK_TYPE MANUAL -BACK_VALUE 0 -THRESH_TYPE "
      "ABSOLUTE -DETECT_MINAREA 3 -CHECKIMAGE_TYPE SEGMENTATION";
  ASSERT_EQ(test::runSourceExtractor(dir, "img.fits",
                                     "-DETECT_THRESH 3 -CHECKIMAGE_NAME s1.fits" + common),
            0);
  ASSERT_EQ(test::runSourceExtractor(dir, "img.fits",
                                     "-DETECT_THRESH 15 -CHECKIMAGE_NAME s2.fits" + common),
            0);
  const std::vector<ImageI32> levels = {test::readFits<std::int32_t>(dir / "s1.fits"),
                                        test::readFits<std::int32_t>(dir / "s2.fits")};
  const auto segments = segmentsFromLabels(levels, {"s1.fits", "s2.fits"});

  std::map<std::pair<int, std::int32_t>, const Segment*> byKey;
  for (const Segment& s : segments) byKey[{s.level, s.number}] = &s;
  int atLevel2 = 0;
  std::set<std::int32_t> parentsAtLevel2;
  for (const Segment& s : segments) {
    for (std::int64_t p : s.pixels) {
      ASSERT_GT(image[p], s.level == 1 ? 3.0f : 15.0f);
      ASSERT_EQ(levels[s.level - 1][p], s.number);
    }
    if (s.level == 2) {
      ++atLevel2;
      parentsAtLevel2.insert(s.parentNumber);
      const Segment* parent = byKey.at({1, s.parentNumber});
      const std::set<std::int64_t> parentPixels(parent->pixels.begin(), parent->pixels.end());
      for (std::int64_t p : s.pixels) EXPECT_TRUE(parentPixels.count(p));
    }
  }
  // The pair separates at 15: two level-2 objects share one parent; the third source has its own.
  EXPECT_EQ(atLevel2, 3);
  EXPECT_EQ(parentsAtLevel2.size(), 2u);
}

}  // namespace
}  // namespace octarc
