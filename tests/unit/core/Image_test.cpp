#include "octarc/core/Image.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

constexpr std::int64_t kInt64Max = std::numeric_limits<std::int64_t>::max();

TEST(Image, SizesAndIndices) {
  const ImageF image(7, 3, 2.5f);
  EXPECT_EQ(image.size(), 21);
  EXPECT_EQ(image.index(4, 2), 18);
  EXPECT_FLOAT_EQ(image(6, 2), 2.5f);
  EXPECT_TRUE(ImageF(0, 5).empty());
}

TEST(Image, PixelCountOfLegalSizes) {
  EXPECT_EQ(checkedPixelCount(0, 0, 4), 0);
  EXPECT_EQ(checkedPixelCount(100000, 100000, 4), 10000000000);
  // The largest count whose float pixels are addressable: PTRDIFF_MAX / 4 = 2^61 - 1 (rounded
  // down), e.g. 2^30 x (2^31 - 1).
  EXPECT_EQ(checkedPixelCount(std::int64_t(1) << 30, (std::int64_t(1) << 31) - 1, 4),
            (std::int64_t(1) << 61) - (std::int64_t(1) << 30));
}

TEST(Image, OverflowingSizesAreRefusedBeforeAllocation) {
  // 2^63 - 1 x 1 and 2^62 x 4 (whose product wraps to 0 in 64 bits) are what fuzzed FITS
  // headers produced; neither may overflow or reach the allocator.
  EXPECT_THROW(checkedPixelCount(kInt64Max, 1, 4), Error);
  EXPECT_THROW(checkedPixelCount(std::int64_t(1) << 62, 4, 4), Error);
  EXPECT_THROW(checkedPixelCount(std::int64_t(1) << 32, std::int64_t(1) << 32, 1), Error);
  EXPECT_THROW(checkedPixelCount(std::int64_t(1) << 31, std::int64_t(1) << 30, 4), Error);
  EXPECT_THROW(checkedPixelCount(-1, 10, 4), Error);
  EXPECT_THROW(checkedPixelCount(10, -1, 4), Error);
  EXPECT_THROW(ImageF(kInt64Max, 1), Error);
  EXPECT_THROW(ImageI32(std::int64_t(1) << 62, 4, UninitializedPixels{}), Error);
  try {
    ImageD(kInt64Max, 2);
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("9223372036854775807 x 2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace octarc
