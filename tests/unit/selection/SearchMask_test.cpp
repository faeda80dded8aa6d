#include "octarc/selection/SearchMask.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "ExpectError.h"
#include "FitsHeaders.h"
#include "octarc/io/FitsHeader.h"

namespace octarc {
namespace {

using test::imageHeader;

std::vector<RegionShape> regions(const std::string& text) {
  return parseDs9Regions(text, "mask.reg", imageHeader(20, 20), "image.fits");
}

TEST(SearchMask, BorderMarginLeavesTheInnerRectangle) {
  SearchMaskSettings settings;
  settings.borderPix = 2;
  const SearchMask mask(10, 8, settings);
  EXPECT_EQ(mask.searchedPixelCount(), (10 - 4) * (8 - 4));
  EXPECT_FALSE(mask.searched(2.0, 4.0));  // 0-based column 1
  EXPECT_TRUE(mask.searched(3.0, 4.0));
  EXPECT_TRUE(mask.searched(8.4, 6.4));   // pixel (8, 6), 0-based (7, 5)
  EXPECT_FALSE(mask.searched(8.6, 6.4));  // pixel (9, 6)
  // Pixel i (1-based) covers [i - 0.5, i + 0.5): 0.5 is in pixel 1, 10.5 is off the image.
  SearchMaskSettings whole;
  const SearchMask all(10, 8, whole);
  EXPECT_TRUE(all.searched(0.5, 1.0));
  EXPECT_FALSE(all.searched(0.49, 1.0));
  EXPECT_TRUE(all.searched(10.49, 8.49));
  EXPECT_FALSE(all.searched(10.5, 1.0));
  EXPECT_FALSE(mask.searched(0.0, 4.0));  // outside the image
}

// A circle of radius 3 centred on a pixel holds the 29 pixel centres with dx^2 + dy^2 <= 9
// (Gauss's circle problem for r = 3).
TEST(SearchMask, BlockCountsAddUpTheSearchedPixelsOfEachBlock) {
  // 130 x 70 pixels, a 5-pixel border: searched x in [5, 124], y in [5, 64] (0-based). Blocks
  // of 64: columns [0, 63], [64, 127], [128, 129]; rows [0, 63], [64, 69].
  SearchMaskSettings settings;
  settings.borderPix = 5;
  const SearchMask mask(130, 70, settings);
  ASSERT_EQ(SearchMask::kAreaBlockPix, 64);
  const Image<std::int32_t>& blocks = mask.blockCounts();
  ASSERT_EQ(blocks.width(), 3);
  ASSERT_EQ(blocks.height(), 2);
  EXPECT_EQ(blocks(0, 0), 59 * 59);
  EXPECT_EQ(blocks(1, 0), 61 * 59);
  EXPECT_EQ(blocks(2, 0), 0);
  EXPECT_EQ(blocks(0, 1), 59);  // the row y = 64 only
  EXPECT_EQ(blocks(1, 1), 61);
  EXPECT_EQ(blocks(2, 1), 0);
  EXPECT_EQ(mask.searchedPixelCount(), 120 * 60);
  // Block centres, 1-based: the first block [0, 63] is centred on 32.5; the cut last one
  // [128, 129] on 129.5.
  EXPECT_DOUBLE_EQ(blockCentreFits(0, 64, 130), 32.5);
  EXPECT_DOUBLE_EQ(blockCentreFits(2, 64, 130), 129.5);
}

TEST(SearchMask, CircleHoldsTheLatticePointsOfGausssCircle) {
  SearchMaskSettings settings;
  settings.regions = regions("image; circle(10,10,3)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 29);
  settings.regions = regions("image; -circle(10,10,3)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 400 - 29);
  // A 7 x 7 box around the same centre holds all 29 and 20 more: the box minus the circle.
  settings.regions = regions("image; box(10,10,7,7); -circle(10,10,3)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 49 - 29);
  // An annulus of radii 1.5 and 3 holds the 29 minus the 9 with dx^2 + dy^2 < 2.25; two
  // include shapes search their union, and an exclude-only file cuts from the whole image.
  settings.regions = regions("image; annulus(10,10,1.5,3)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 29 - 9);
  settings.regions = regions("image; circle(5,5,3); circle(15,15,3)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 2 * 29);
  settings.regions = regions("image; -circle(5,5,3); -annulus(15,15,1.5,3)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 400 - 29 - 20);
  // A shape partly off the image counts only the pixels inside it.
  settings.regions = regions("image; box(1,1,5,5)\n");
  EXPECT_EQ(SearchMask(20, 20, settings).searchedPixelCount(), 3 * 3);
}

// Painting shape by shape inside bounding boxes gives DS9's rule (regionContains) at every
// pixel centre, for rotated boxes and ellipses, a polygon, annuli and shapes over the edge.
TEST(SearchMask, EveryPixelFollowsTheRegionRule) {
  SearchMaskSettings settings;
  settings.regions = regions(
      "image\n"
      "ellipse(6.3,7.9,6.5,2.2,33)\n"
      "box(15.2,4.1,9.5,3.3,-62)\n"
      "-ellipse(8,8,2.5,1.2,100)\n"
      "polygon(12,12,19.5,13,14,21.7,16,15)\n"
      "-box(20,20,4,6,45)\n"
      "annulus(4.2,15.7,1.6,3.9)\n"
      "-annulus(13.5,9.5,1.1,2.7)\n");
  const SearchMask mask(20, 20, settings);
  std::int64_t count = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const bool want = regionContains(settings.regions, x + 1.0, y + 1.0);
      EXPECT_EQ(mask.searchedPixel(x, y), want) << x << "," << y;
      count += want;
    }
  }
  EXPECT_EQ(mask.searchedPixelCount(), count);
  EXPECT_GT(count, 50);
  EXPECT_LT(count, 400 - 50);
}

TEST(SearchMask, InfiniteVarianceMasksPixels) {
  ImageF variance(6, 5, 1.0f);
  variance(2, 3) = std::numeric_limits<float>::infinity();
  variance(4, 0) = std::numeric_limits<float>::infinity();
  SearchMaskSettings settings;
  settings.varianceAdu2 = &variance;
  const SearchMask mask(6, 5, settings);
  EXPECT_EQ(mask.searchedPixelCount(), 30 - 2);
  EXPECT_FALSE(mask.searchedPixel(2, 3));
  EXPECT_FALSE(mask.searched(5.0, 1.0));
}

// An image of 0.2 arcsec pixels: 300 x 200 pixels cover 60" x 40" = 6.1728e-5 deg2 (a TAN
// projection 30" from its centre changes the pixel area by about 1e-8).
TEST(SearchMask, AreaFromTheWcsPixelArea) {
  FitsHeader h = imageHeader(300, 200);
  h.set("CTYPE1", "'RA---TAN'");
  h.set("CTYPE2", "'DEC--TAN'");
  h.set("CRPIX1", "150.5");
  h.set("CRPIX2", "100.5");
  h.set("CRVAL1", "0.002");  // the longitude wraps through 0 inside the image (+-0.0096 deg)
  h.set("CRVAL2", "-30.0");
  h.set("CD1_1", "-5.5555555555555556E-05");
  h.set("CD2_2", "5.5555555555555556E-05");
  const auto wcs = Wcs::fromHeader(h, "image.fits");
  ASSERT_TRUE(wcs.has_value());
  const double pixelAreaDeg2 = std::pow(0.2 / 3600.0, 2);
  SearchMaskSettings settings;
  EXPECT_NEAR(SearchMask(300, 200, settings).searchedAreaDeg2(*wcs) / (300 * 200 * pixelAreaDeg2),
              1.0, 1e-6);
  settings.borderPix = 10;
  EXPECT_NEAR(SearchMask(300, 200, settings).searchedAreaDeg2(*wcs) / (280 * 180 * pixelAreaDeg2),
              1.0, 1e-6);
}

TEST(SearchMask, BadSettingsAreConfigErrors) {
  ImageF variance(4, 4, 1.0f);
  SearchMaskSettings settings;
  settings.varianceAdu2 = &variance;
  test::expectError<ConfigError>([&] { SearchMask(5, 4, settings); }, {"4x4", "5x4"});
  settings.varianceAdu2 = nullptr;
  settings.borderPix = -1;
  test::expectError<ConfigError>([&] { SearchMask(5, 4, settings); }, {"border", "-1"});
}

}  // namespace
}  // namespace octarc
