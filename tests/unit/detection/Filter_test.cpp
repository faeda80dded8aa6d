#include "octarc/detection/Filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>

#include "ConvKernels.h"
#include "DetectionTestUtil.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

// An asymmetric mask: every coefficient differs, so any flip or transposition shows.
ConvKernel asymmetric3x3() {
  return ConvKernel{3, 3, {1, 2, 3, 4, 5, 6, 7, 8, 9}};
}

TEST(Filter, DeltaResponseShowsTheMaskFlippedAndFirstLineBelow) {
  ImageF image(7, 6, 0.0f);
  image(3, 2) = 1.0f;
  const ImageF out = applyFilter(image, asymmetric3x3());
  // Correlation: out(x, y) = sum k[j][i] in(x + i - 1, y + j - 1), so the delta at (3, 2)
  // reaches out(3 - (i - 1), 2 - (j - 1)) with weight k[j][i].
  EXPECT_FLOAT_EQ(out(4, 3), 1.0f);  // k[0][0]: first line, first column
  EXPECT_FLOAT_EQ(out(2, 3), 3.0f);  // k[0][2]
  EXPECT_FLOAT_EQ(out(3, 2), 5.0f);  // centre
  EXPECT_FLOAT_EQ(out(4, 1), 7.0f);  // k[2][0]: last line
  EXPECT_FLOAT_EQ(out(2, 1), 9.0f);  // k[2][2]
  double total = 0.0;
  for (float v : out.pixels()) total += v;
  EXPECT_DOUBLE_EQ(total, 45.0);
}

TEST(Filter, ZeroPaddingWithoutRenormalisationAtEdges) {
  // Constant image of 2: an interior pixel sees the full mask sum (45 * 2); the corner (0, 0)
  // sees only the coefficients whose source pixel lies inside: k[1][1], k[1][2], k[2][1],
  // k[2][2] = 5 + 6 + 8 + 9 = 28, times 2.
  const ImageF image(5, 4, 2.0f);
  const ImageF out = applyFilter(image, asymmetric3x3());
  EXPECT_FLOAT_EQ(out(2, 1), 90.0f);
  EXPECT_FLOAT_EQ(out(0, 0), 56.0f);
  // Top-right corner (4, 3): k[0][0], k[0][1], k[1][0], k[1][1] = 1 + 2 + 4 + 5 = 12.
  EXPECT_FLOAT_EQ(out(4, 3), 24.0f);
  // Bottom edge (2, 0): rows j = 1, 2 only: 4+5+6+7+8+9 = 39.
  EXPECT_FLOAT_EQ(out(2, 0), 78.0f);
}

TEST(Filter, NonSquareMaskAndTinyImage) {
  // 5 wide, 1 high mask on a 3x1 image: out(x) = sum_i k[i] in(x + i - 2).
  const ConvKernel k{5, 1, {1, 10, 100, 1000, 10000}};
  ImageF image(3, 1);
  image[0] = 1.0f;
  image[1] = 2.0f;
  image[2] = 3.0f;
  const ImageF out = applyFilter(image, k);
  EXPECT_FLOAT_EQ(out[0], 10.0f * 0 + 100.0f * 1 + 1000.0f * 2 + 10000.0f * 3);
  EXPECT_FLOAT_EQ(out[1], 10.0f * 1 + 100.0f * 2 + 1000.0f * 3);
  EXPECT_FLOAT_EQ(out[2], 1.0f * 1 + 10.0f * 2 + 100.0f * 3);
}

TEST(Filter, NonFinitePixelsCountAsZeroAndStayNonFinite) {
  ImageF image(4, 4, 1.0f);
  image(1, 1) = std::numeric_limits<float>::quiet_NaN();
  image(3, 3) = std::numeric_limits<float>::infinity();
  const ConvKernel box{3, 3, {1, 1, 1, 1, 1, 1, 1, 1, 1}};
  const ImageF out = applyFilter(image, box);
  EXPECT_TRUE(std::isnan(out(1, 1)));
  EXPECT_TRUE(std::isinf(out(3, 3)));
  EXPECT_FLOAT_EQ(out(2, 1), 8.0f);  // nine neighbours, one of them NaN
  EXPECT_FLOAT_EQ(out(0, 0), 3.0f);  // corner: four in the image, one NaN
  EXPECT_FLOAT_EQ(out(2, 2), 7.0f);  // sees both the NaN and the Inf
}

TEST(Filter, ThreadCountDoesNotChangeTheResult) {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  ImageF image(131, 97);
  for (float& v : image.pixels()) v = noise(rng);
  image(40, 50) = std::numeric_limits<float>::quiet_NaN();
  const ConvKernel k{5, 3, {1, -2, 3, 0.5f, 7, -1, 4, 9, 2, -3, 6, 0, 1, 8, -5}};
  const ImageF one = applyFilter(image, k, 1);
  for (int threads : {2, 3, 200}) {
    const ImageF many = applyFilter(image, k, threads);
    ASSERT_EQ(many.size(), one.size());
    for (std::int64_t i = 0; i < one.size(); ++i) {
      if (std::isnan(one[i])) {
        ASSERT_TRUE(std::isnan(many[i])) << i;
      } else {
        ASSERT_EQ(many[i], one[i]) << "pixel " << i << ", threads " << threads;
      }
    }
  }
}

TEST(Filter, RejectsInconsistentMask) {
  const ImageF image(4, 4, 1.0f);
  EXPECT_THROW(applyFilter(image, ConvKernel{3, 3, {1, 2, 3}}), ConfigError);
  EXPECT_THROW(applyFilter(image, ConvKernel{0, 0, {}}), ConfigError);
}

// source-extractor's FILTERED check-image of a random float image, with the mask given as a
// .conv file, against applyFilter with the same mask built by hand.
void compareFilterWithSourceExtractor(const std::string& convText, const ConvKernel& kernel,
                                      std::uint32_t seed) {
  const auto dir = test::scratchDir();
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 10.0f);
  ImageF image(61, 47);
  for (float& v : image.pixels()) v = noise(rng);
  image(30, 20) = 500.0f;  // a bright point so the threshold finds something
  test::writeFloatFits(dir / "img.fits", image);
  std::ofstream(dir / "mask.conv") << convText;
  ASSERT_EQ(
      test::runSourceExtractor(dir, "img.fits",
                               "-FILTER Y -FILTER_NAME mask.conv -BACK_TYPE MANUAL -BACK_VALUE 0"
                               " -THRESH_TYPE ABSOLUTE -DETECT_THRESH 100 -CHECKIMAGE_TYPE FILTERED"
                               " -CHECKIMAGE_NAME f.fits"),
      0);
  const ImageF reference = test::readFits<float>(dir / "f.fits");
  const ImageF out = applyFilter(image, kernel);
  ASSERT_EQ(reference.width(), out.width());
  ASSERT_EQ(reference.height(), out.height());
  // The README's claim: the filtered image equals SExtractor's FILTERED check-image, pixel for
  // pixel (the same products summed in the same order in single precision).
  std::int64_t differing = 0;
  double worst = 0.0;
  for (std::int64_t i = 0; i < out.size(); ++i) {
    if (out[i] != reference[i]) ++differing;
    worst = std::max(worst, std::fabs(double(out[i]) - double(reference[i])));
  }
  EXPECT_EQ(differing, 0) << "largest difference " << worst;
}

TEST(Filter, MatchesSourceExtractorAsymmetricMask) {
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  compareFilterWithSourceExtractor("CONV NONORM\n1 2 3\n4 5 6\n7 8 9\n", asymmetric3x3(), 11);
}

TEST(Filter, MatchesSourceExtractorDefaultConv) {
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  // default.conv: CONV NORM, normalised by the sum of |k| = 16.
  const ConvKernel k = test::defaultConvKernel();
  const auto dir = test::scratchDir();
  std::ifstream in("/usr/share/source-extractor/default.conv");
  ASSERT_TRUE(in) << "default.conv not installed";
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  compareFilterWithSourceExtractor(text, k, 12);
}

TEST(Filter, MatchesSourceExtractorWideAsymmetricMask) {
  OCTARC_REQUIRE_SOURCE_EXTRACTOR();
  // 5 columns x 3 rows with negative values, raw (NONORM).
  const ConvKernel k{5, 3, {1, -2, 3, 0.5f, 7, -1, 4, 9, 2, -3, 6, 0, 1, 8, -5}};
  compareFilterWithSourceExtractor("CONV NONORM\n1 -2 3 0.5 7\n-1 4 9 2 -3\n6 0 1 8 -5\n", k, 13);
}

}  // namespace
}  // namespace octarc
