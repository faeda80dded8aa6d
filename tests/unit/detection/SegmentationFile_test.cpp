#include <gtest/gtest.h>

#include "DetectionTestUtil.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/detection/SegmentationReader.h"

namespace octarc {
namespace {

std::string readError(const std::vector<std::string>& paths, std::int64_t w, std::int64_t h) {
  try {
    readSegmentation(paths, w, h);
  } catch (const IoError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SegmentationFile, ReadsTwoLevelsFromFits) {
  const auto dir = test::scratchDir();
  ImageI32 low(4, 3, 0);
  low(1, 1) = low(2, 1) = low(2, 2) = 3;
  ImageI32 high(4, 3, 0);
  high(2, 1) = 1;
  test::writeIntFits(dir / "l1.fits", low);
  test::writeIntFits(dir / "l2.fits", high);
  const auto segments =
      readSegmentation({(dir / "l1.fits").string(), (dir / "l2.fits").string()}, 4, 3);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_EQ(segments[0].number, 3);
  EXPECT_EQ(segments[0].pixels, (std::vector<std::int64_t>{5, 6, 10}));
  EXPECT_EQ(segments[1].number, 1);
  EXPECT_EQ(segments[1].level, 2);
  EXPECT_EQ(segments[1].parentNumber, 3);
  EXPECT_EQ(segments[1].pixels, (std::vector<std::int64_t>{6}));
}

TEST(SegmentationFile, RejectsWrongSizeNamingBothSizes) {
  const auto dir = test::scratchDir();
  const std::string path = (dir / "seg.fits").string();
  test::writeIntFits(path, ImageI32(5, 4, 0));
  EXPECT_EQ(readError({path}, 6, 4), path + ": segmentation image is 5x4 but the image is 6x4");
}

TEST(SegmentationFile, RejectsFloatImageNamingTheFile) {
  const auto dir = test::scratchDir();
  const std::string path = (dir / "float.fits").string();
  test::writeFloatFits(path, ImageF(3, 3, 1.0f));
  const std::string msg = readError({path}, 3, 3);
  EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
  EXPECT_NE(msg.find("integer"), std::string::npos) << msg;
}

TEST(SegmentationFile, RejectsMissingFile) {
  const auto dir = test::scratchDir();
  const std::string path = (dir / "missing.fits").string();
  const std::string msg = readError({path}, 3, 3);
  EXPECT_NE(msg.find("missing.fits"), std::string::npos) << msg;
}

TEST(SegmentationFile, NestingErrorNamesBothFiles) {
  const auto dir = test::scratchDir();
  ImageI32 low(3, 1, 0);
  low[0] = 1;
  ImageI32 high(3, 1, 0);
  high[1] = 2;
  const std::string a = (dir / "a.fits").string();
  const std::string b = (dir / "b.fits").string();
  test::writeIntFits(a, low);
  test::writeIntFits(b, high);
  EXPECT_EQ(
      readError({a, b}, 3, 1),
      b + ": label 2 at level 2 has FITS pixel (2, 1) on the background of level 1 (" + a +
          "); the levels do not nest (give SEGMENTATION_NAME and DETECT_LEVELS lowest threshold "
          "first)");
}

}  // namespace
}  // namespace octarc
