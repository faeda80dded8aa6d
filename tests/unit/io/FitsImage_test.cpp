#include "octarc/io/FitsImage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "ExpectError.h"
#include "FitsTestFiles.h"
#include "TestCommands.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;
using test::card;
using test::FitsWriter;

struct BitpixCase {
  int bitpix;
  double bscale;
  double bzero;
  std::vector<double> raw;  // stored values
};

TEST(FitsImage, EveryBitpixWithScalingReadsPhysicalValues) {
  const fs::path dir = test::scratchDir();
  const std::vector<BitpixCase> cases = {
      {8, 1.0, -128.0, {0, 1, 127, 128, 200, 255}},                        // signed bytes
      {16, 1.0, 32768.0, {-32768, -1, 0, 1, 1000, 32767}},                 // unsigned 16-bit
      {32, 2.0, 10.0, {-5, 0, 7, 1000000, -1000000, 3}},                   // scaled 32-bit
      {64, 1.0, 0.0, {-1099511627776.0, 0, 1, 2, 4096, 1099511627776.0}},  // 2^40, exact in float
      {-32, 0.5, 1.0, {3.0, -2.5, 0.0, 1e6, 0.25, -7.0}},
      {-64, 1.0, 0.0, {0.1, -3.75, 1e-20, 6.5e30, 0.0, 2.0}},
  };
  for (const BitpixCase& c : cases) {
    const fs::path path = dir / ("bitpix" + std::to_string(c.bitpix) + ".fits");
    std::vector<std::string> cards;
    if (c.bscale != 1.0 || c.bzero != 0.0) {
      cards = {card("BSCALE", std::to_string(c.bscale)), card("BZERO", std::to_string(c.bzero))};
    }
    FitsWriter(path).image(c.bitpix, {3, 2}, c.raw, cards);
    const ImageHdu hdu = readImage(path.string());
    SCOPED_TRACE("BITPIX " + std::to_string(c.bitpix));
    EXPECT_EQ(hdu.bitpix, c.bitpix);
    EXPECT_EQ(hdu.hduIndex, 0);
    EXPECT_EQ(hdu.path, path.string());
    ASSERT_EQ(hdu.pixels.width(), 3);
    ASSERT_EQ(hdu.pixels.height(), 2);
    for (std::size_t i = 0; i < c.raw.size(); ++i) {
      const float expected = static_cast<float>(c.raw[i] * c.bscale + c.bzero);
      EXPECT_EQ(hdu.pixels[static_cast<std::int64_t>(i)], expected) << "pixel " << i;
    }
    // Row order: the second row (y = 1) starts with the fourth stored value.
    EXPECT_EQ(hdu.pixels(0, 1), static_cast<float>(c.raw[3] * c.bscale + c.bzero));
    EXPECT_EQ(hdu.header.number("NAXIS1"), 3.0);
  }
}

TEST(FitsImage, BlankAndNanPixelsBecomeNan) {
  const fs::path dir = test::scratchDir();
  FitsWriter(dir / "blank.fits")
      .image(16, {2, 2}, {5, -1, 7, -1}, {card("BLANK", "-1"), card("BZERO", "100")});
  const ImageHdu hdu = readImage((dir / "blank.fits").string());
  EXPECT_EQ(hdu.pixels[0], 105.0f);
  EXPECT_TRUE(std::isnan(hdu.pixels[1]));
  EXPECT_EQ(hdu.pixels[2], 107.0f);
  EXPECT_TRUE(std::isnan(hdu.pixels[3]));

  FitsWriter(dir / "nan.fits").image(-32, {2, 1}, {std::nan(""), 4.0});
  const ImageHdu f = readImage((dir / "nan.fits").string());
  EXPECT_TRUE(std::isnan(f.pixels[0]));
  EXPECT_EQ(f.pixels[1], 4.0f);
}

// Empty primary, SCI image, a table, WHT image.
fs::path writeMef(const fs::path& dir) {
  const fs::path path = dir / "mef.fits";
  FitsWriter(path)
      .emptyPrimary()
      .image(-32, {2, 2}, {1, 2, 3, 4}, {card("EXTNAME", "'SCI'"), card("GAIN", "2.0")})
      .table("CAT")
      .image(16, {2, 2}, {10, 20, 30, 40}, {card("EXTNAME", "'WHT'")});
  return path;
}

TEST(FitsImage, MefListingSkipsEmptyPrimaryAndTables) {
  const fs::path dir = test::scratchDir();
  const std::string path = writeMef(dir).string();
  EXPECT_EQ(listImageHdus(path), (std::vector<std::string>{path + "[1]", path + "[3]"}));
  EXPECT_EQ(listImageHdus(path + "[WHT]"), std::vector<std::string>{path + "[WHT]"});

  // A plain single image gives the path unchanged; an image primary plus an image extension
  // gives both.
  FitsWriter(dir / "plain.fits").image(-32, {2, 2}, {1, 2, 3, 4});
  EXPECT_EQ(listImageHdus((dir / "plain.fits").string()),
            std::vector<std::string>{(dir / "plain.fits").string()});
  FitsWriter(dir / "two.fits").image(-32, {2, 2}, {1, 2, 3, 4}).image(-32, {1, 1}, {5});
  const std::string two = (dir / "two.fits").string();
  EXPECT_EQ(listImageHdus(two), (std::vector<std::string>{two + "[0]", two + "[1]"}));
}

TEST(FitsImage, ExtendedSyntaxSelectsHduByNumberAndName) {
  const fs::path dir = test::scratchDir();
  const std::string path = writeMef(dir).string();
  const ImageHdu sci = readImage(path + "[SCI]");
  EXPECT_EQ(sci.hduIndex, 1);
  EXPECT_EQ(sci.extname, "SCI");
  EXPECT_EQ(sci.header.number("GAIN"), 2.0);
  EXPECT_EQ(sci.pixels(1, 1), 4.0f);
  const ImageHdu wht = readImage(path + "[3]");
  EXPECT_EQ(wht.hduIndex, 3);
  EXPECT_EQ(wht.extname, "WHT");
  EXPECT_EQ(wht.bitpix, 16);
  EXPECT_EQ(wht.pixels(0, 1), 30.0f);
  // A plain path reads the first image that holds data.
  EXPECT_EQ(readImage(path).extname, "SCI");
  // Header only: same header and size, no pixels.
  const ImageHdu header = readImageHeader(path + "[WHT]");
  EXPECT_EQ(header.extname, "WHT");
  EXPECT_EQ(header.header.number("NAXIS2"), 2.0);
  EXPECT_EQ(header.widthPix, 2);
  EXPECT_EQ(header.heightPix, 2);
  EXPECT_TRUE(header.pixels.empty());
  // Every listed path reads back.
  for (const std::string& p : listImageHdus(path)) EXPECT_NO_THROW(readImage(p));
}

TEST(FitsImage, TileCompressedFileReadsLikeTheOriginal) {
  const fs::path dir = test::scratchDir();
  const fs::path original = dir / "plain.fits";
  std::vector<double> raw;
  for (int i = 0; i < 40 * 30; ++i) raw.push_back((i * 37) % 2001 - 1000);
  FitsWriter(original).image(
      16, {40, 30}, raw,
      {card("BZERO", "32768"), card("CRPIX1", "20.5"), card("CTYPE1", "'RA---TAN'")});
  ASSERT_EQ(test::run("cd '" + dir.string() + "' && fpack plain.fits"), 0) << "fpack failed";
  const std::string packed = (dir / "plain.fits.fz").string();
  ASSERT_TRUE(fs::exists(packed));

  EXPECT_EQ(listImageHdus(packed), std::vector<std::string>{packed + "[1]"});
  const ImageHdu a = readImage(original.string());
  const ImageHdu b = readImage(packed);
  EXPECT_EQ(b.hduIndex, 1);
  EXPECT_EQ(b.bitpix, 16);
  ASSERT_EQ(b.pixels.width(), 40);
  ASSERT_EQ(b.pixels.height(), 30);
  EXPECT_EQ(a.pixels.pixels(), b.pixels.pixels());
  EXPECT_EQ(b.pixels(1, 0), 32768.0f - 963.0f);  // raw 37 - 1000, + BZERO
  // The header is the uncompressed image header, not the binary table's.
  EXPECT_EQ(b.header.value("CTYPE1"), "RA---TAN");
  EXPECT_EQ(b.header.number("NAXIS1"), 40.0);
  // The size of the image, not of the table that holds it, also from the header alone.
  const ImageHdu packedHeader = readImageHeader(packed);
  EXPECT_EQ(packedHeader.widthPix, 40);
  EXPECT_EQ(packedHeader.heightPix, 30);
  EXPECT_EQ(b.header.number("BITPIX"), 16.0);
  EXPECT_FALSE(b.header.has("ZIMAGE"));
  EXPECT_FALSE(b.header.has("TFIELDS"));
  EXPECT_EQ(readImage(packed + "[1]").pixels.pixels(), a.pixels.pixels());
}

// A large float image is read straight from the file on several threads; scaled, gzipped and
// tile-compressed ones go through cfitsio. All must give the stored values, NaN included.
TEST(FitsImage, LargeFloatImagesReadTheSameWhicheverWay) {
  const fs::path dir = test::scratchDir();
  const long width = 2111, height = 2003;  // > 4 M pixels: several reading threads
  std::vector<double> raw(std::size_t(width * height));
  for (std::size_t i = 0; i < raw.size(); ++i) {
    raw[i] = i % 99991 == 7 ? std::nan("") : double(i % 4093) * 0.25 - 300.0;
  }
  auto expectStored = [&](const ImageHdu& hdu, double scale, double zero) {
    ASSERT_EQ(hdu.pixels.width(), width);
    ASSERT_EQ(hdu.pixels.height(), height);
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const float v = hdu.pixels[std::int64_t(i)];
      if (std::isnan(raw[i])) {
        ASSERT_TRUE(std::isnan(v)) << "pixel " << i;
      } else {
        ASSERT_EQ(v, float(raw[i] * scale + zero)) << "pixel " << i;
      }
    }
  };
  FitsWriter(dir / "big.fits").emptyPrimary().image(-32, {width, height}, raw);
  expectStored(readImage((dir / "big.fits").string() + "[1]"), 1.0, 0.0);
  FitsWriter(dir / "bigscaled.fits").image(-32, {width, height}, raw, {card("BZERO", "10.0")});
  expectStored(readImage((dir / "bigscaled.fits").string()), 1.0, 10.0);
  // Compressed by gzip itself: cfitsio writing a .gz grows its memory file by realloc, which
  // the sanitizers' allocator turns into a copy of the whole file per step.
  FitsWriter(dir / "bigprimary.fits").image(-32, {width, height}, raw);
  ASSERT_EQ(test::run("gzip -c '" + (dir / "bigprimary.fits").string() + "' > '" +
                      (dir / "big.fits.gz").string() + "'"),
            0);
  expectStored(readImage((dir / "big.fits.gz").string()), 1.0, 0.0);
}

// Found by fuzzing (a leak under LeakSanitizer): a tile-compressed float image whose ZSCALE
// column is not declared makes cfitsio fail while it rebuilds the image header, and the header
// text it had allocated was not freed.
TEST(FitsImage, CompressedImageWhoseHeaderCannotBeRebuiltIsAnIoError) {
  const fs::path dir = test::scratchDir();
  std::vector<double> raw;
  for (int i = 0; i < 8 * 6; ++i) raw.push_back(0.37 * i - 3.0);
  FitsWriter(dir / "float.fits").image(-32, {8, 6}, raw);
  ASSERT_EQ(test::run("cd '" + dir.string() + "' && fpack float.fits"), 0) << "fpack failed";
  std::string bytes = test::readFile(dir / "float.fits.fz");
  const std::size_t at = bytes.find("= 'ZSCALE");
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(bytes.compare(at - 8, 5, "TTYPE"), 0);
  bytes.replace(at - 8, 5, "TPYPE");  // the column keeps its TFORM but loses its name
  const fs::path broken = dir / "broken.fits.fz";
  std::ofstream(broken, std::ios::binary) << bytes;
  test::expectIoError([&] { readImageHeader(broken.string()); },
                      {broken.string(), "cannot read header"});
  test::expectIoError([&] { readImage(broken.string()); }, {broken.string()});
}

// Found by fuzzing (a segmentation fault in cfitsio): the HCOMPRESS decoder takes the tile size
// from the stream and writes that many pixels into a buffer of the tile's size. A stream that
// states another size is refused before cfitsio decodes it; real HCOMPRESS files still read.
TEST(FitsImage, HcompressTileStatingAnotherSizeIsRefused) {
  const fs::path dir = test::scratchDir();
  std::vector<double> raw;
  for (int i = 0; i < 40 * 30; ++i) raw.push_back((i * 37) % 2001 - 1000);
  FitsWriter(dir / "plain.fits").image(32, {40, 30}, raw);
  ASSERT_EQ(test::run("cd '" + dir.string() + "' && fpack -h -s 0 -w plain.fits"), 0)
      << "fpack failed";
  const fs::path packed = dir / "plain.fits.fz";
  const ImageHdu a = readImage((dir / "plain.fits").string());
  const ImageHdu b = readImage(packed.string());  // lossless (scale 0): the same pixels
  EXPECT_EQ(a.pixels.pixels(), b.pixels.pixels());
  EXPECT_EQ(readIntImage(packed.string())(1, 0), 37 - 1000);

  std::string bytes = test::readFile(packed);
  const std::size_t stream = bytes.find("\xdd\x99");
  ASSERT_NE(stream, std::string::npos);
  bytes.replace(stream + 2, 4, std::string("\x00\x1e\x00\x00", 4));  // nx = 1966080
  const fs::path bad = dir / "bad.fits.fz";
  std::ofstream(bad, std::ios::binary) << bytes;
  test::expectIoError([&] { readImage(bad.string()); },
                      {bad.string() + ": HDU 1: HCOMPRESS tile 1", "40 x 30 tile"});
  test::expectIoError([&] { readIntImage(bad.string()); },
                      {bad.string() + ": HDU 1: HCOMPRESS tile 1"});
  // The magic number itself.
  bytes[stream] = 'x';
  std::ofstream(bad, std::ios::binary) << bytes;
  test::expectIoError([&] { readImage(bad.string()); }, {bad.string(), "is not a stream"});
}

TEST(FitsImage, DegenerateThirdAxisIsAccepted) {
  const fs::path dir = test::scratchDir();
  FitsWriter(dir / "cube1.fits").image(-32, {2, 2, 1}, {1, 2, 3, 4});
  const ImageHdu hdu = readImage((dir / "cube1.fits").string());
  EXPECT_EQ(hdu.pixels.width(), 2);
  EXPECT_EQ(hdu.pixels(1, 1), 4.0f);
}

TEST(FitsImage, BadInputGivesOneLineIoErrorNamingTheFile) {
  const fs::path dir = test::scratchDir();
  const std::string missing = (dir / "missing.fits").string();
  test::expectIoError([&] { readImage(missing); }, {missing});
  test::expectIoError([&] { listImageHdus(missing); }, {missing});

  const fs::path text = dir / "notfits.fits";
  { std::ofstream(text) << "this is not a FITS file\n" << std::string(3000, 'x'); }
  test::expectIoError([&] { readImage(text.string()); }, {text.string()});

  // Truncated: the header promises 100x100 floats, the file stops half way through the data.
  const fs::path truncated = dir / "truncated.fits";
  FitsWriter(truncated).image(-32, {100, 100}, std::vector<double>(10000, 1.0));
  fs::resize_file(truncated, 2880 + 20000);
  test::expectIoError([&] { readImage(truncated.string()); }, {truncated.string(), "truncated"});
  test::expectIoError([&] { readImageHeader(truncated.string()); },
                      {truncated.string(), "truncated"});
  test::expectIoError([&] { readIntImage(truncated.string()); }, {truncated.string(), "truncated"});

  const std::string mef = writeMef(dir).string();
  test::expectIoError([&] { readImage(mef + "[2]"); }, {mef, "binary table"});
  test::expectIoError([&] { readImage(mef + "[CAT]"); }, {mef, "not an image"});
  test::expectIoError([&] { listImageHdus(mef + "[2]"); }, {mef, "not an image"});

  const fs::path tableOnly = dir / "tableonly.fits";
  FitsWriter(tableOnly).emptyPrimary().table("CAT");
  test::expectIoError([&] { readImage(tableOnly.string()); }, {tableOnly.string(), "no image"});
  test::expectIoError([&] { listImageHdus(tableOnly.string()); }, {tableOnly.string(), "no image"});

  const fs::path oneD = dir / "oned.fits";
  FitsWriter(oneD).image(-32, {5}, {1, 2, 3, 4, 5});
  test::expectIoError([&] { readImage(oneD.string()); }, {oneD.string(), "NAXIS = 1"});
  const fs::path cube = dir / "cube.fits";
  FitsWriter(cube).image(-32, {2, 2, 2}, {1, 2, 3, 4, 5, 6, 7, 8});
  test::expectIoError([&] { readImage(cube.string()); }, {cube.string(), "NAXIS3 = 2"});
  test::expectIoError([&] { listImageHdus(cube.string()); }, {cube.string(), "NAXIS = 3"});
}

// Sizes no file can hold are refused from the header, before any allocation, naming the file,
// the HDU and the size, by every reader (images, headers, segmentation images). These headers
// come from mutation fuzzing: 2^63 - 1 overflowed in Image, 2^62 x 4 wrapped to 0 pixels.
TEST(FitsImage, SizesTheFileCannotHoldAreRefusedBeforeAllocation) {
  const fs::path dir = test::scratchDir();
  struct Case {
    const char* name;
    int bitpix;
    std::vector<std::string> axes;
    const char* fragment;
  };
  const std::vector<Case> cases = {
      {"max63.fits", -32, {"9223372036854775807", "1"}, "9223372036854775807 x 1"},
      {"wraps.fits", -32, {"4611686018427387904", "4"}, "4611686018427387904 x 4"},
      {"max63seg.fits", 32, {"1", "9223372036854775807"}, "1 x 9223372036854775807"},
      // 100000 x 100000 floats: 40 GB promised by a file of two blocks.
      {"huge.fits", -32, {"100000", "100000"}, "40000000000 bytes"},
      {"hugeseg.fits", 16, {"100000", "100000"}, "20000000000 bytes"},
  };
  for (const Case& c : cases) {
    const fs::path path = dir / c.name;
    test::writeRawFits(path, {{test::primaryCards(c.bitpix, c.axes), 400}});
    const std::string file = path.string();
    test::expectIoError([&] { readImage(file); }, {file + ": HDU 0", c.fragment});
    test::expectIoError([&] { readImageHeader(file); }, {file + ": HDU 0", c.fragment});
    test::expectIoError([&] { readIntImage(file); }, {file + ": HDU 0", c.fragment});
    test::expectIoError([&] { listImageHdus(file); }, {file + ": HDU 0", c.fragment});
  }
  // The same in an extension of a multi-extension file names that HDU.
  const fs::path mef = dir / "mef.fits";
  std::vector<std::string> ext = {card("XTENSION", "'IMAGE   '"),
                                  card("BITPIX", "-32"),
                                  card("NAXIS", "2"),
                                  card("NAXIS1", "3000"),
                                  card("NAXIS2", "3000"),
                                  card("PCOUNT", "0"),
                                  card("GCOUNT", "1")};
  test::writeRawFits(mef, {{test::primaryCards(8, {}, {card("EXTEND", "T")}), 0}, {ext, 36}});
  test::expectIoError([&] { listImageHdus(mef.string()); },
                      {mef.string() + ": HDU 1", "truncated"});
  test::expectIoError([&] { readImage(mef.string()); },
                      {mef.string() + ": HDU 1", "36000000 bytes"});
  test::expectIoError([&] { readImage(mef.string() + "[1]"); },
                      {mef.string() + ": HDU 1", "truncated"});
}

TEST(FitsImage, ZeroAxisOfATwoDimensionalImageIsRefused) {
  const fs::path dir = test::scratchDir();
  const fs::path path = dir / "zero.fits";
  test::writeRawFits(path, {{test::primaryCards(-32, {"0", "10"}), 0}});
  test::expectIoError([&] { readImage(path.string()); },
                      {path.string() + ": HDU 0", "0 x 10 pixels"});
  test::expectIoError([&] { readIntImage(path.string()); }, {path.string() + ": HDU 0", "0 x 10"});
  test::expectIoError([&] { listImageHdus(path.string()); }, {path.string() + ": HDU 0", "0 x 10"});
}

TEST(FitsImage, ExtensionOfUnknownTypeIsRefused) {
  // cfitsio takes any XTENSION for an image; 'FOO' must not be read as pixels.
  const fs::path dir = test::scratchDir();
  const fs::path path = dir / "foo.fits";
  const std::vector<std::string> ext = {card("XTENSION", "'FOO     '"),
                                        card("BITPIX", "-32"),
                                        card("NAXIS", "2"),
                                        card("NAXIS1", "2"),
                                        card("NAXIS2", "2"),
                                        card("PCOUNT", "0"),
                                        card("GCOUNT", "1")};
  test::writeRawFits(path, {{test::primaryCards(8, {}, {card("EXTEND", "T")}), 0}, {ext, 16}});
  for (const std::string& p : {path.string(), path.string() + "[1]"}) {
    test::expectIoError([&] { readImage(p); }, {path.string() + ": HDU 1", "XTENSION 'FOO'"});
    test::expectIoError([&] { listImageHdus(p); }, {path.string() + ": HDU 1", "XTENSION 'FOO'"});
  }
}

// BSCALE/BZERO/BLANK that are not numbers were ignored or replaced by cfitsio, so that a file
// was read with other pixel values than it states. Both readers (the raw float reader and
// cfitsio's) must refuse them, naming the file, the HDU and the keyword with its value.
TEST(FitsImage, ScalingKeywordsThatAreNotNumbersAreRefused) {
  const fs::path dir = test::scratchDir();
  struct Case {
    int bitpix;
    std::string key;
    std::string value;
    std::string shown;
  };
  const std::vector<Case> cases = {
      {-32, "BSCALE", "'x'", "BSCALE = 'x'"},   {16, "BSCALE", "'x'", "BSCALE = 'x'"},
      {-32, "BSCALE", "NaN", "BSCALE = 'NaN'"}, {16, "BSCALE", "NaN", "BSCALE = 'NaN'"},
      {-32, "BSCALE", "0", "BSCALE = '0'"},     {16, "BSCALE", "0.0", "BSCALE = '0.0'"},
      {-32, "BZERO", "'x'", "BZERO = 'x'"},     {16, "BZERO", "'x'", "BZERO = 'x'"},
      {-32, "BZERO", "Inf", "BZERO = 'Inf'"},   {32, "BZERO", "0x10", "BZERO = '0x10'"},
      {16, "BLANK", "'x'", "BLANK = 'x'"},      {16, "BLANK", "1.5", "BLANK = '1.5'"},
      {32, "BLANK", "NaN", "BLANK = 'NaN'"},
  };
  int k = 0;
  for (const Case& c : cases) {
    const fs::path path = dir / ("scaling" + std::to_string(k++) + ".fits");
    test::writeRawFits(path, {{test::primaryCards(c.bitpix, {"10", "10"}, {card(c.key, c.value)}),
                               std::size_t(100 * std::abs(c.bitpix) / 8)}});
    const std::string where = path.string() + ": HDU 0: " + c.shown;
    test::expectIoError([&] { readImage(path.string()); }, {where, "cannot be interpreted"});
    test::expectIoError([&] { readImageHeader(path.string()); }, {where, "cannot be interpreted"});
    if (c.bitpix > 0) test::expectIoError([&] { readIntImage(path.string()); }, {where});
  }
  // BLANK means nothing for floating-point data (NaN marks undefined pixels): ignored there.
  const fs::path floatBlank = dir / "floatblank.fits";
  test::writeRawFits(floatBlank,
                     {{test::primaryCards(-32, {"10", "10"}, {card("BLANK", "'x'")}), 400}});
  const ImageHdu hdu = readImage(floatBlank.string());
  EXPECT_EQ(hdu.pixels(9, 9), 0.0f);
}

TEST(FitsImage, ExplicitUnitScalingOfFloatsReadsTheStoredValues) {
  // BSCALE = 1 and BZERO = 0 written out are the same as no scaling (the raw reader applies).
  const fs::path dir = test::scratchDir();
  const fs::path path = dir / "unit.fits";
  FitsWriter(path).image(-32, {3, 1}, {1.5, -2.25, 1e30},
                         {card("BSCALE", "1.0"), card("BZERO", "0.0")});
  const ImageHdu hdu = readImage(path.string());
  EXPECT_EQ(hdu.pixels[0], 1.5f);
  EXPECT_EQ(hdu.pixels[1], -2.25f);
  EXPECT_EQ(hdu.pixels[2], 1e30f);
}

// Found by fuzzing: cfitsio 4.2 copies a TTYPEn value into a 70-byte buffer with strcpy, so an
// unquoted value of 70 characters (or one after "=" without the blank) aborted octarc with
// "buffer overflow detected". Such a header is refused before cfitsio parses it.
TEST(FitsImage, UnquotedTableColumnNameIsRefusedBeforeCfitsioReadsIt) {
  const fs::path dir = test::scratchDir();
  const std::vector<std::string> table = {card("XTENSION", "'BINTABLE'"),
                                          card("BITPIX", "8"),
                                          card("NAXIS", "2"),
                                          card("NAXIS1", "4"),
                                          card("NAXIS2", "1"),
                                          card("PCOUNT", "0"),
                                          card("GCOUNT", "1"),
                                          card("TFIELDS", "1"),
                                          card("TFORM1", "'J'")};
  const std::vector<std::string> image = {card("XTENSION", "'IMAGE   '"),
                                          card("BITPIX", "-32"),
                                          card("NAXIS", "2"),
                                          card("NAXIS1", "2"),
                                          card("NAXIS2", "2"),
                                          card("PCOUNT", "0"),
                                          card("GCOUNT", "1")};
  const std::vector<std::string> names = {"TTYPE1  = " + std::string(70, 'A'),
                                          "TTYPE1  =" + std::string(71, '\xa8'),
                                          "TTYPE1  = NUMBER"};
  int k = 0;
  for (const std::string& name : names) {
    const fs::path path = dir / ("ttype" + std::to_string(k++) + ".fits");
    std::vector<std::string> cards = table;
    cards.push_back(name);
    test::writeRawFits(
        path, {{test::primaryCards(8, {}, {card("EXTEND", "T")}), 0}, {cards, 4}, {image, 16}});
    // Every reader goes through the same open: also for the image after the table.
    test::expectIoError([&] { listImageHdus(path.string()); },
                        {path.string() + ": HDU 1: 'TTYPE1'", "is not a quoted string"});
    test::expectIoError([&] { readImage(path.string() + "[2]"); },
                        {path.string() + ": HDU 1: 'TTYPE1'"});
  }
  // The same file with a quoted name reads.
  const fs::path good = dir / "good.fits";
  std::vector<std::string> cards = table;
  cards.push_back(card("TTYPE1", "'NUMBER'"));
  test::writeRawFits(
      good, {{test::primaryCards(8, {}, {card("EXTEND", "T")}), 0}, {cards, 4}, {image, 16}});
  EXPECT_EQ(listImageHdus(good.string()), std::vector<std::string>{good.string() + "[2]"});
}

// Found by fuzzing: cfitsio sizes its buffer for a gzip file from the ISIZE trailer (for a zip
// file from its local header), so a 1 KB file could make it allocate 4 GB. A stated size that
// no deflate stream of the file's length can reach (1032 to 1) is refused.
TEST(FitsImage, CompressedFileStatingAnImpossibleSizeIsRefused) {
  const fs::path dir = test::scratchDir();
  const fs::path gz = dir / "image.fits.gz";
  FitsWriter(gz).image(-32, {4, 3}, std::vector<double>(12, 1.5));
  EXPECT_EQ(readImage(gz.string()).pixels(3, 2), 1.5f);  // cfitsio writes it gzip-compressed
  std::string bytes = test::readFile(gz);
  ASSERT_EQ(bytes.substr(0, 2), "\x1f\x8b");
  bytes.replace(bytes.size() - 4, 4, "\xff\xff\xff\xff");  // ISIZE: 4294967295 bytes
  const fs::path lying = dir / "lying.fits.gz";
  std::ofstream(lying, std::ios::binary) << bytes;
  test::expectIoError([&] { readImage(lying.string()); },
                      {lying.string(), "states an uncompressed size of 4294967295 bytes"});
  test::expectIoError([&] { listImageHdus(lying.string() + "[0]"); }, {lying.string()});
  // The same bytes under a name without .gz: cfitsio looks at the content, and so does octarc.
  const fs::path plain = dir / "lying.fits";
  fs::copy_file(lying, plain);
  test::expectIoError([&] { readImageHeader(plain.string()); }, {plain.string(), "4294967295"});
  // A zip file states the size at byte 22.
  std::string zip =
      "PK\x03\x04" + std::string(18, '\0') + "\xff\xff\xff\x7f" + std::string(100, 'x');
  const fs::path zipped = dir / "image.zip";
  std::ofstream(zipped, std::ios::binary) << zip;
  test::expectIoError([&] { readImage(zipped.string()); }, {zipped.string(), "2147483647 bytes"});
}

TEST(FitsImage, ReadIntImageIsExactAndRejectsNonIntegerImages) {
  const fs::path dir = test::scratchDir();
  // 2147483000 has no exact float representation: the int path must not go through float.
  const fs::path seg = dir / "seg.fits";
  FitsWriter(seg).image(32, {3, 1}, {0, 7, 2147483000.0}, {card("CRVAL1", "12.5")});
  FitsHeader header;
  const ImageI32 labels = readIntImage(seg.string(), &header);
  ASSERT_EQ(labels.width(), 3);
  EXPECT_EQ(labels[0], 0);
  EXPECT_EQ(labels[1], 7);
  EXPECT_EQ(labels[2], 2147483000);
  EXPECT_EQ(header.number("CRVAL1"), 12.5);

  const fs::path u16 = dir / "u16.fits";  // unsigned 16-bit: integer BZERO is still integer
  FitsWriter(u16).image(16, {2, 1}, {-32768, 32767}, {card("BZERO", "32768")});
  const ImageI32 u = readIntImage(u16.string());
  EXPECT_EQ(u[0], 0);
  EXPECT_EQ(u[1], 65535);

  const fs::path flt = dir / "float.fits";
  FitsWriter(flt).image(-32, {2, 1}, {1, 2});
  test::expectIoError([&] { readIntImage(flt.string()); }, {flt.string(), "not an integer image"});
  const fs::path scaled = dir / "scaled.fits";
  FitsWriter(scaled).image(16, {2, 1}, {1, 2}, {card("BSCALE", "2.0")});
  test::expectIoError([&] { readIntImage(scaled.string()); },
                      {scaled.string(), "not an integer image"});
  const fs::path big = dir / "big.fits";
  FitsWriter(big).image(64, {2, 1}, {1, 4294967296.0});
  test::expectIoError([&] { readIntImage(big.string()); }, {big.string(), "32-bit"});
}

// fitsverify -q prints one summary line and exits with the number of errors plus warnings.
void expectFitsverifyOk(const fs::path& path) {
  const fs::path log = path.string() + ".verify";
  const int rc = test::run("fitsverify -q '" + path.string() + "' > '" + log.string() + "' 2>&1");
  EXPECT_EQ(rc, 0) << test::readFile(log);
  EXPECT_NE(test::readFile(log).find("verification OK"), std::string::npos) << test::readFile(log);
}

TEST(FitsImage, WriteImageFileRoundTripsIntAndFloatKeepingWcsCards) {
  const fs::path dir = test::scratchDir();
  FitsHeader header;
  header.cards = {
      card("SIMPLE", "T"),          card("BITPIX", "16"),     card("NAXIS", "2"),
      card("NAXIS1", "999"),        card("NAXIS2", "999"),    card("BZERO", "32768"),
      card("BSCALE", "1"),          card("BLANK", "-1"),      card("CTYPE1", "'RA---TAN'"),
      card("CTYPE2", "'DEC--TAN'"), card("CRVAL1", "150.25"), card("CRPIX1", "12.0"),
      card("CD1_1", "-2.8E-05")};
  header.set("HISTORY", "made by the test");

  ImageI32 labels(4, 3, 0);
  labels(1, 1) = 2;
  labels(3, 2) = 2147483000;
  labels(0, 2) = -5;
  const fs::path segPath = dir / "seg.fits";
  writeImageFile(segPath.string(), {{header, nullptr, &labels}});
  expectFitsverifyOk(segPath);
  FitsHeader back;
  const ImageI32 read = readIntImage(segPath.string(), &back);
  EXPECT_EQ(read.pixels(), labels.pixels());
  EXPECT_EQ(back.number("BITPIX"), 32.0);
  EXPECT_EQ(back.number("NAXIS1"), 4.0);
  EXPECT_EQ(back.value("CTYPE2"), "DEC--TAN");
  EXPECT_EQ(back.number("CRVAL1"), 150.25);
  EXPECT_EQ(back.number("CD1_1"), -2.8e-05);
  EXPECT_FALSE(back.has("BZERO"));
  EXPECT_FALSE(back.has("BLANK"));
  int history = 0;
  for (const std::string& c : back.cards) history += c.rfind("HISTORY made by the test", 0) == 0;
  EXPECT_EQ(history, 1);

  ImageF values(3, 2, 0.0f);
  values(0, 0) = 1.5f;
  values(2, 1) = -1e30f;
  values(1, 0) = std::nanf("");
  const fs::path floatPath = dir / "float.fits";
  writeImageFile(floatPath.string(), {{header, &values, nullptr}});
  expectFitsverifyOk(floatPath);
  const ImageHdu f = readImage(floatPath.string());
  EXPECT_EQ(f.bitpix, -32);
  EXPECT_EQ(f.pixels(0, 0), 1.5f);
  EXPECT_EQ(f.pixels(2, 1), -1e30f);
  EXPECT_TRUE(std::isnan(f.pixels(1, 0)));
  EXPECT_EQ(f.header.value("CTYPE1"), "RA---TAN");

  // Writing again replaces the file, and no temporary file is left behind.
  values(0, 0) = 2.5f;
  writeImageFile(floatPath.string(), {{header, &values, nullptr}});
  EXPECT_EQ(readImage(floatPath.string()).pixels(0, 0), 2.5f);
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST(FitsImage, WriteImageFileWithSeveralHdusWritesMef) {
  const fs::path dir = test::scratchDir();
  FitsHeader h1;
  h1.set("EXTNAME", quoteFitsString("CHIP1"));
  h1.set("XTENSION", quoteFitsString("IMAGE"));  // structural: replaced, not duplicated
  FitsHeader h2;
  h2.set("EXTNAME", quoteFitsString("CHIP2"));
  ImageI32 a(2, 2, 1);
  ImageF b(3, 1, 0.5f);
  const fs::path path = dir / "check.fits";
  writeImageFile(path.string(), {{h1, nullptr, &a}, {h2, &b, nullptr}});
  expectFitsverifyOk(path);
  const std::string p = path.string();
  EXPECT_EQ(listImageHdus(p), (std::vector<std::string>{p + "[1]", p + "[2]"}));
  const ImageHdu chip1 = readImageHeader(p + "[CHIP1]");
  EXPECT_EQ(chip1.hduIndex, 1);
  EXPECT_EQ(chip1.bitpix, 32);
  const ImageHdu chip2 = readImage(p + "[CHIP2]");
  EXPECT_EQ(chip2.hduIndex, 2);
  EXPECT_EQ(chip2.bitpix, -32);
  EXPECT_EQ(chip2.pixels(2, 0), 0.5f);
  EXPECT_EQ(readIntImage(p + "[1]").pixels(), a.pixels());
}

TEST(FitsImage, WriteImageFileSequentialFillsOneHduAtATime) {
  const fs::path dir = test::scratchDir();
  const fs::path path = dir / "levels.fits";
  ImageI32 labels;  // one buffer reused for every HDU
  std::vector<int> calls;
  writeImageFileSequential(path.string(), 3, [&](int k, OutputImageHdu& hdu) {
    calls.push_back(k);
    EXPECT_EQ(hdu.intPixels, nullptr);  // a fresh HDU each time
    EXPECT_TRUE(hdu.header.cards.empty());
    labels = ImageI32(2, 2, 10 * (k + 1));
    hdu.header.set("EXTNAME", quoteFitsString("LEVEL" + std::to_string(k + 1)));
    hdu.intPixels = &labels;
  });
  EXPECT_EQ(calls, (std::vector<int>{0, 1, 2}));
  expectFitsverifyOk(path);
  const std::string p = path.string();
  ASSERT_EQ(listImageHdus(p).size(), 3u);
  EXPECT_EQ(readIntImage(p + "[LEVEL1]")[0], 10);
  EXPECT_EQ(readIntImage(p + "[LEVEL3]")[3], 30);
  EXPECT_EQ(readImageHeader(p + "[2]").extname, "LEVEL2");

  // A single HDU is a primary image, as with writeImageFile.
  const fs::path single = dir / "single.fits";
  writeImageFileSequential(single.string(), 1, [&](int, OutputImageHdu& hdu) {
    labels = ImageI32(1, 1, 4);
    hdu.intPixels = &labels;
  });
  EXPECT_EQ(listImageHdus(single.string()), std::vector<std::string>{single.string()});
  // A failure part way leaves no file.
  const fs::path failed = dir / "failed.fits";
  EXPECT_THROW(writeImageFileSequential(failed.string(), 2,
                                        [&](int k, OutputImageHdu& hdu) {
                                          if (k == 1) throw IoError("stop");
                                          labels = ImageI32(1, 1, 4);
                                          hdu.intPixels = &labels;
                                        }),
               IoError);
  EXPECT_FALSE(fs::exists(failed));
}

TEST(FitsImage, WriteImageFileFailureLeavesNoFile) {
  const fs::path dir = test::scratchDir();
  ImageF empty;
  const fs::path path = dir / "never.fits";
  test::expectIoError(
      [&] {
        writeImageFile(path.string(), {{FitsHeader{}, &empty, nullptr}});
      },
      {path.string()});
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir));
  const fs::path noDir = dir / "no-such-dir" / "out.fits";
  ImageF one(1, 1, 1.0f);
  EXPECT_THROW(writeImageFile(noDir.string(), {{FitsHeader{}, &one, nullptr}}), IoError);
}

TEST(FitsImage, RealNttImageMatchesAstropy) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path image = shared / "ntt-emmi" / "galaxies.fits";
  const fs::path dir = test::scratchDir();
  const fs::path out = dir / "astropy.txt";
  // astropy's data array is indexed [y, x] with 0-based indices.
  const std::string script =
      "import warnings\n"
      "from astropy.io import fits\n"
      "warnings.simplefilter('ignore')\n"
      "d = fits.getdata('" +
      image.string() +
      "')\n"
      "print(d.shape[1], d.shape[0])\n"
      "for x, y in [(0, 0), (511, 300), (1023, 1023), (17, 900)]:\n"
      "    print(repr(float(d[y, x])))\n";
  { std::ofstream(dir / "read.py") << script; }
  ASSERT_EQ(
      test::run("/usr/bin/python3 '" + (dir / "read.py").string() + "' > '" + out.string() + "'"),
      0);
  std::ifstream in(out);
  long width = 0;
  long height = 0;
  in >> width >> height;
  const ImageHdu hdu = readImage(image.string());
  EXPECT_EQ(hdu.bitpix, 16);
  ASSERT_EQ(hdu.pixels.width(), width);
  ASSERT_EQ(hdu.pixels.height(), height);
  const int xs[] = {0, 511, 1023, 17};
  const int ys[] = {0, 300, 1023, 900};
  for (int i = 0; i < 4; ++i) {
    double expected = 0.0;
    in >> expected;
    // astropy scales in single precision, cfitsio in double then rounds: 1 float ulp apart at
    // most.
    const float e = float(expected);
    EXPECT_LE(std::fabs(hdu.pixels(xs[i], ys[i]) - e),
              std::nextafter(std::fabs(e), INFINITY) - std::fabs(e))
        << xs[i] << "," << ys[i];
  }
  EXPECT_EQ(listImageHdus(image.string()), std::vector<std::string>{image.string()});
}

}  // namespace
}  // namespace octarc
