// What an inspector gets from a hand-made search result: the region marks, the stamps (cut-out,
// display range, marks, no captions), each value known in advance.
#include "octarc/search/Inspection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

// The lens circle of 1" then has a radius of 4 pixels.
constexpr double kArcsecPerPixel = 0.25;

// Rows: 0 the first candidate's arc, 1 its lens, 2 the second candidate's arc (no lens).
Table inspectedCatalog() {
  using T = ColumnType;
  Table t({{"X_IMAGE", "", "pixel", "", T::Float32, "%10.3f"},
           {"Y_IMAGE", "", "pixel", "", T::Float32, "%10.3f"},
           {"A_IMAGE", "", "pixel", "", T::Float32, "%9.3f"},
           {"B_IMAGE", "", "pixel", "", T::Float32, "%9.3f"},
           {"THETA_IMAGE", "", "deg", "", T::Float32, "%5.1f"},
           {"ARCNESS", "", "", "", T::Float32, "%8.4f"},
           {"E_IMAGE", "", "", "", T::Float32, "%7.4f"},
           {"SNR_ISO", "", "", "", T::Float32, "%10.2f"},
           {"MAG_ISO", "", "mag", "", T::Float32, "%8.4f"}});
  const std::vector<std::vector<double>> rows = {{10.5, 20.25, 4, 1.5, 30, 0.1875, 0.75, 55, 21.5},
                                                 {15.5, 25.5, 6, 5, -10, 0.01, 0.1, 300, 19},
                                                 {100, 50, 3, 1, 90, 0.125, 0.625, 42, 22.25}};
  for (const auto& r : rows) {
    double* out = t.appendRow();
    for (std::size_t c = 0; c < r.size(); ++c) out[c] = r[c];
  }
  return t;
}

SearchResult inspectedResult() {
  SearchResult r;
  Candidate a;
  a.row = 0;
  a.passedLevels = {2, 3};
  a.lensScore = 0.125;
  a.probability = 0.5;
  a.contourLevel = 0.75;
  a.name = "OCTARC J095950.40+021000.0";
  a.lens = CandidateLens{1, 15.5, 25.5, 149.961, 2.167, 1.75};
  Candidate b;
  b.row = 2;
  b.passedLevels = {3};
  b.lensScore = 0.0625;
  b.probability = 0.25;
  b.flags = kCandidateDarkLens;
  r.candidates = {a, b};
  return r;
}

TEST(Inspection, RegionMarksAreArcEllipsesAndLensCircles) {
  const std::vector<RegionMark> marks =
      candidateRegionMarks(inspectedCatalog(), inspectedResult(), kArcsecPerPixel);
  ASSERT_EQ(marks.size(), 3u);  // arc 1, its lens, arc 2 (no lens)
  EXPECT_EQ(marks[0].kind, RegionShapeKind::Ellipse);
  EXPECT_EQ(marks[0].xCentre, 10.5);
  EXPECT_EQ(marks[0].yCentre, 20.25);
  EXPECT_EQ(marks[0].semiAxis1Pix, 12.0);  // 3 A_IMAGE
  EXPECT_EQ(marks[0].semiAxis2Pix, 4.5);   // 3 B_IMAGE
  EXPECT_NEAR(marks[0].angleRad, std::numbers::pi / 6, 1e-12);
  EXPECT_EQ(marks[0].colour, "green");
  EXPECT_EQ(marks[0].text, "1");
  EXPECT_EQ(marks[1].kind, RegionShapeKind::Circle);
  EXPECT_EQ(marks[1].xCentre, 15.5);
  EXPECT_EQ(marks[1].yCentre, 25.5);
  EXPECT_EQ(marks[1].semiAxis1Pix, 4.0);  // 1" at 0.25"/px
  EXPECT_EQ(marks[1].colour, "red");
  EXPECT_EQ(marks[2].text, "2");
  EXPECT_EQ(marks[2].semiAxis1Pix, 9.0);
  EXPECT_NEAR(marks[2].angleRad, std::numbers::pi / 2, 1e-12);
}

TEST(Inspection, StampFileNamesAreNumberedFromOne) {
  EXPECT_EQ(stampFileName(0), "stamps/0001.png");
  EXPECT_EQ(stampFileName(122), "stamps/0123.png");
}

TEST(Inspection, StampCutsAroundTheLensWithTheDisplayRangeOfItsPixels) {
  // A 4" stamp at 0.25"/px is 16 px. Candidate 1's lens is at 1-based (15.5, 25.5), 0-based
  // (14.5, 24.5): centre pixel (15, 25), cut-out from (7, 17). There the image holds 0 ... 255,
  // each once; elsewhere 1000.
  ImageF image(104, 80, 1000.0f);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) image(7 + i, 17 + j) = float(i + 16 * j);
  StampSettings settings;
  settings.sideArcsec = 4.0;
  settings.sizePix = 123;
  const Table catalog = inspectedCatalog();
  const SearchResult result = inspectedResult();
  const Stamp s = candidateStamp(image, catalog, result, 0, nullptr, kArcsecPerPixel, settings);
  ASSERT_EQ(s.pixels.width(), 16);
  ASSERT_EQ(s.pixels.height(), 16);
  EXPECT_EQ(s.xFirstFits, 8.0);
  EXPECT_EQ(s.yFirstFits, 18.0);
  EXPECT_EQ(s.pixels(0, 0), 0.0f);
  EXPECT_EQ(s.pixels(15, 15), 255.0f);
  EXPECT_EQ(s.pixels(3, 2), 35.0f);
  // Quantiles of 0 ... 255 (at (n - 1) q): median 127.5, 15.87 % 40.4685, 99.7 % 254.235.
  // Black one robust sigma below the median, white at the 99.7th percentile.
  EXPECT_NEAR(s.displayLowAdu, 127.5 - (127.5 - 40.4685), 1e-9);
  EXPECT_NEAR(s.displayHighAdu, 254.235, 1e-9);
  EXPECT_FALSE(s.hasSkyDirections);  // no WCS
  EXPECT_EQ(s.pixelScaleArcsec, kArcsecPerPixel);
  EXPECT_EQ(s.sizePix, 123);
  ASSERT_EQ(s.marks.size(), 2u);
  EXPECT_TRUE(s.marks[0].ellipse);
  EXPECT_EQ(s.marks[0].xFits, 10.5);
  EXPECT_EQ(s.marks[0].semiAxis1Pix, 12.0);
  EXPECT_FALSE(s.marks[1].ellipse);
  EXPECT_EQ(s.marks[1].xFits, 15.5);
  EXPECT_EQ(s.marks[1].semiAxis1Pix, 4.0);
  // No text burnt in: the vetting page captions the stamp.
  EXPECT_EQ(s.marks[1].label, "");
  EXPECT_EQ(s.title, "");
  EXPECT_EQ(s.subtitle, "");

  // Candidate 2, without a lens, is centred on its arc: 1-based (100, 50), cut-out from
  // 0-based (91, 41); columns 104 ... 106 lie outside the image and stay NaN.
  const Stamp t = candidateStamp(image, catalog, result, 1, nullptr, kArcsecPerPixel, settings);
  EXPECT_EQ(t.xFirstFits, 92.0);
  EXPECT_EQ(t.yFirstFits, 42.0);
  EXPECT_EQ(t.pixels(12, 0), 1000.0f);
  EXPECT_TRUE(std::isnan(t.pixels(13, 0)));
  EXPECT_TRUE(std::isnan(t.pixels(15, 15)));
  EXPECT_EQ(t.marks.size(), 1u);
  // Every finite pixel 1000: a flat range, widened to one ADU.
  EXPECT_EQ(t.displayLowAdu, 1000.0);
  EXPECT_EQ(t.displayHighAdu, 1001.0);
  EXPECT_THROW(candidateStamp(image, catalog, result, 2, nullptr, kArcsecPerPixel, settings),
               std::out_of_range);
}

TEST(Inspection, CutoutHeaderShiftsTheWcsToTheCutout) {
  EXPECT_EQ(cutoutFileName(0), "stamps/0001.fits");
  EXPECT_EQ(cutoutFileName(122), "stamps/0123.fits");
  FitsHeader image;
  image.set("CRPIX1", "50.5");
  image.set("CRPIX2", "60");
  image.set("CRVAL1", "150.0");
  Stamp stamp;
  stamp.xFirstFits = 8;  // the cut-out's pixel (1, 1) is the image's (8, 18)
  stamp.yFirstFits = 18;
  const FitsHeader cut = cutoutHeader(image, stamp);
  EXPECT_EQ(cut.number("CRPIX1"), 43.5);
  EXPECT_EQ(cut.number("CRPIX2"), 43.0);
  EXPECT_EQ(cut.number("CRVAL1"), 150.0);
  // DS9's physical coordinates: image = cut-out - LTV.
  EXPECT_EQ(cut.number("LTV1"), -7.0);
  EXPECT_EQ(cut.number("LTV2"), -17.0);
  EXPECT_EQ(cut.number("LTM1_1"), 1.0);
  // A cut-out of that cut-out: its pixel (1, 1) is the first one's (8, 18), i.e. the image's
  // (15, 35): physical = image - LTV with LTV = -14, -34.
  const FitsHeader again = cutoutHeader(cut, stamp);
  EXPECT_EQ(again.number("LTV1"), -14.0);
  EXPECT_EQ(again.number("LTV2"), -34.0);
  EXPECT_EQ(again.number("CRPIX1"), 36.5);
  // Without a WCS, none is made up.
  EXPECT_FALSE(cutoutHeader(FitsHeader(), stamp).has("CRPIX1"));
}

TEST(Inspection, ColourStampFileNameIsBesideTheStamp) {
  EXPECT_EQ(colourStampFileName(0), "stamps/0001.colour.png");
  EXPECT_EQ(colourStampFileName(122), "stamps/0123.colour.png");
}

TEST(Inspection, ColourStampScalesBandsByZeroPointAndKeepsTheCutOut) {
  // r (searched, zero point 30) 1000 ADU everywhere; g (29.5) 1000 / 10^0.2 ADU, the same
  // flux on r's scale: grey. Sky sigma 10: softening 150, Q I / S = 5 x 1000 / 150, each channel
  // asinh(33.333) / 5 = 0.84003, 214.2 of 255.
  const float equalFlux = float(1000.0 / std::pow(10.0, 0.2));
  ImageF red(104, 80, 1000.0f), green(104, 80, equalFlux);
  green(15, 25) = std::nanf("");  // no g data: black
  StampSettings settings;
  settings.sideArcsec = 4.0;
  const Stamp grey = candidateStamp(red, inspectedCatalog(), inspectedResult(), 0, nullptr,
                                    kArcsecPerPixel, settings);
  const Stamp c = candidateColourStamp(grey, {&red, 30.0}, {{&green, 29.5}}, 10.0);
  ASSERT_EQ(c.rgbPixels.width(), 16);
  ASSERT_EQ(c.rgbPixels.height(), 16);
  EXPECT_TRUE(c.marks.empty());
  EXPECT_EQ(c.xFirstFits, grey.xFirstFits);
  EXPECT_EQ(c.rgbPixels(0, 0), 0xd6d6d6u);  // 214 in each channel
  // Image pixel (15, 25) is the cut-out's (15 - 7, 25 - 17).
  EXPECT_EQ(c.rgbPixels(8, 8), 0u);
  EXPECT_EQ(c.rgbPixels(7, 8), 0xd6d6d6u);
  // Two other bands: blue the first, green the second, red the searched band.
  const ImageF none(104, 80, 0.0f);
  const Stamp yellow =
      candidateColourStamp(grey, {&red, 30.0}, {{&none, 30.0}, {&red, 30.0}}, 10.0);
  const std::uint32_t p = yellow.rgbPixels(0, 0);
  EXPECT_EQ(p >> 16, (p >> 8) & 0xffu);
  EXPECT_GT(p >> 16, 0u);
  EXPECT_EQ(p & 0xffu, 0u);
  EXPECT_THROW(candidateColourStamp(grey, {&red, 30.0}, {}, 10.0), ConfigError);
}

}  // namespace
}  // namespace octarc
