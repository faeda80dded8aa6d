#include "octarc/io/Ds9Region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ExpectError.h"
#include "FitsHeaders.h"
#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17G", v);
  return text;
}

using test::Cards;

// A 400 x 300 image with these cards.
FitsHeader makeHeader(const Cards& cards) {
  return test::imageHeader(400, 300, cards);
}

// A TAN WCS at 0.2 arcsec per pixel, North rotated 30 degrees from +y, East to the left.
constexpr double kScaleDeg = 0.2 / 3600.0;
constexpr double kRotationRad = 30.0 * kRadPerDeg;
const Cards kSkyCards = {{"CTYPE1", "'RA---TAN'"},
                         {"CTYPE2", "'DEC--TAN'"},
                         {"CRPIX1", "200.5"},
                         {"CRPIX2", "150.5"},
                         {"CRVAL1", "150.1"},
                         {"CRVAL2", "2.2"},
                         {"CD1_1", num(-kScaleDeg* std::cos(kRotationRad))},
                         {"CD1_2", num(kScaleDeg* std::sin(kRotationRad))},
                         {"CD2_1", num(kScaleDeg* std::sin(kRotationRad))},
                         {"CD2_2", num(kScaleDeg* std::cos(kRotationRad))},
                         {"RADESYS", "'ICRS'"}};

std::vector<RegionShape> parse(const std::string& text, const Cards& cards = {},
                               double pointRadiusPix = 0.0) {
  return parseDs9Regions(text, "mask.reg", makeHeader(cards), "image.fits", pointRadiusPix);
}

TEST(Ds9Region, ImageCircleBoxEllipsePolygonByHand) {
  const auto shapes = parse(
      "# Region file format: DS9 version 4.1\n"
      "global color=green dashlist=8 3 width=1\n"
      "image\n"
      "circle(100,100,10) # text={star}\n"
      "box(50.5,60,20,10,90)\n"
      "ellipse(200,100,30,10,0)\n"
      "polygon(10,10,30,10,30,30)\n");
  ASSERT_EQ(shapes.size(), 4U);
  const RegionShape& circle = shapes[0];
  EXPECT_EQ(circle.kind, RegionShapeKind::Circle);
  EXPECT_EQ(circle.lineNumber, 4);
  EXPECT_TRUE(circle.contains(109.9, 100.0));
  EXPECT_FALSE(circle.contains(107.2, 107.2));  // distance 10.18
  // A box 20 wide and 10 high turned by 90 degrees: 10 wide and 20 high.
  const RegionShape& box = shapes[1];
  EXPECT_TRUE(box.contains(50.5 + 4.9, 60.0 + 9.9));
  EXPECT_FALSE(box.contains(50.5 + 5.1, 60.0));
  EXPECT_FALSE(box.contains(50.5, 60.0 + 10.1));
  const RegionShape& ellipse = shapes[2];
  EXPECT_TRUE(ellipse.contains(229.9, 100.0));
  EXPECT_FALSE(ellipse.contains(200.0, 110.1));
  EXPECT_TRUE(ellipse.contains(200.0 + 30.0 * 0.6, 100.0 + 10.0 * 0.79));  // 0.36 + 0.6241 < 1
  EXPECT_FALSE(ellipse.contains(200.0 + 30.0 * 0.6, 100.0 + 10.0 * 0.81));
  // The triangle (10,10), (30,10), (30,30): below the diagonal y = x.
  const RegionShape& triangle = shapes[3];
  EXPECT_TRUE(triangle.contains(25.0, 20.0));
  EXPECT_FALSE(triangle.contains(15.0, 20.0));
  EXPECT_FALSE(triangle.contains(31.0, 20.0));
  const auto b = triangle.bounds();
  EXPECT_EQ(b[0], 10.0);
  EXPECT_EQ(b[1], 30.0);
  EXPECT_EQ(b[2], 10.0);
  EXPECT_EQ(b[3], 30.0);
}

TEST(Ds9Region, RotatedBoxAndEllipseBounds) {
  const auto shapes = parse("image; box(0,0,4,2,30); ellipse(0,0,4,2,30)\n");
  ASSERT_EQ(shapes.size(), 2U);
  const double c = std::cos(30.0 * kRadPerDeg);
  const double s = std::sin(30.0 * kRadPerDeg);
  const auto box = shapes[0].bounds();
  EXPECT_NEAR(box[1], 2.0 * c + 1.0 * s, 1e-12);
  EXPECT_NEAR(box[3], 2.0 * s + 1.0 * c, 1e-12);
  const auto ellipse = shapes[1].bounds();
  EXPECT_NEAR(ellipse[1], std::hypot(4.0 * c, 2.0 * s), 1e-12);
  EXPECT_NEAR(ellipse[3], std::hypot(4.0 * s, 2.0 * c), 1e-12);
  // A corner of the rotated box is inside, the same corner unrotated is not.
  EXPECT_TRUE(shapes[0].contains(0.99 * (2.0 * c - 1.0 * s), 0.99 * (2.0 * s + 1.0 * c)));
  EXPECT_FALSE(shapes[0].contains(1.9, 0.99 * (2.0 * s + 1.0 * c)));
}

// DS9's rule: inside an include shape (or no include shape at all), and inside no exclude one,
// whatever the order of the lines.
TEST(Ds9Region, ExcludeShapesCutIncludeShapesInAnyOrder) {
  const auto shapes = parse("image\n-circle(50,50,5)\ncircle(50,50,20)\nbox(100,50,10,10)\n");
  ASSERT_EQ(shapes.size(), 3U);
  EXPECT_TRUE(shapes[0].exclude);
  EXPECT_FALSE(shapes[1].exclude);
  EXPECT_FALSE(regionContains(shapes, 50.0, 50.0));  // in the hole
  EXPECT_TRUE(regionContains(shapes, 60.0, 50.0));
  EXPECT_TRUE(regionContains(shapes, 100.0, 50.0));
  EXPECT_FALSE(regionContains(shapes, 80.0, 50.0));  // in no include shape

  const auto onlyExcludes = parse("image; -circle(50,50,5)\n");
  EXPECT_FALSE(regionContains(onlyExcludes, 51.0, 51.0));
  EXPECT_TRUE(regionContains(onlyExcludes, 300.0, 200.0));  // the rest of the image
  EXPECT_TRUE(regionContains({}, 1.0, 1.0));
}

// Physical coordinates go through LTV / LTM (image = LTM * physical + LTV); no cards = image.
TEST(Ds9Region, PhysicalCoordinatesThroughLtvAndLtm) {
  const auto identity = parse("circle(10,20,3)\n");  // DS9's default system is physical
  EXPECT_EQ(identity[0].xCentre, 10.0);
  EXPECT_EQ(identity[0].semiAxis1Pix, 3.0);
  const auto shifted =
      parse("physical\ncircle(10,20,3)\npolygon(0,0,4,0,4,4)\n",
            {{"LTV1", "-100"}, {"LTV2", "-50"}, {"LTM1_1", "0.5"}, {"LTM2_2", "0.5"}});
  EXPECT_DOUBLE_EQ(shifted[0].xCentre, 0.5 * 10.0 - 100.0);
  EXPECT_DOUBLE_EQ(shifted[0].yCentre, 0.5 * 20.0 - 50.0);
  EXPECT_DOUBLE_EQ(shifted[0].semiAxis1Pix, 1.5);
  EXPECT_DOUBLE_EQ(shifted[1].vertices[1][0], 2.0 - 100.0);
  test::expectError<ConfigError>(
      [] {
        parse("physical; circle(1,1,1)\n", {{"LTM1_1", "0.5"}, {"LTM2_2", "0.25"}});
      },
      {"mask.reg:1", "LTM", "image.fits"});
  // A card that is no number is not taken for its default; image coordinates do not need it.
  test::expectError<ConfigError>(
      [] {
        parse("physical; circle(1,1,1)\n", {{"LTV1", "'-100'"}});
      },
      {"mask.reg:1: physical coordinates, but the LTV1 card of image.fits ('-100') is not a "
       "finite number"});
  EXPECT_EQ(parse("image; circle(4,5,1)\n", {{"LTV1", "'-100'"}})[0].xCentre, 4.0);
}

// fk5 shapes on a rotated TAN WCS: the centre through the WCS, sizes through the pixel scale,
// the angle through the North angle (here 120 degrees from +x).
TEST(Ds9Region, SkyShapesUseTheLocalScaleAndNorthAngle) {
  const auto shapes = parse(
      "fk5\n"
      "circle(150.1,2.2,2\")\n"
      "circle(10:00:24.000,+02:12:00.00,0.05')\n"
      "circle(10h00m24s,2d12m00s,0.000833333333333333d)\n"
      "box(150.1,2.2,4\",2\",0)\n",
      kSkyCards);
  ASSERT_EQ(shapes.size(), 4U);
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(shapes[i].xCentre, 200.5, 1e-6);
    EXPECT_NEAR(shapes[i].yCentre, 150.5, 1e-6);
    EXPECT_NEAR(shapes[i].semiAxis1Pix, i == 0 ? 10.0 : 15.0, 1e-4);
  }
  EXPECT_NEAR(shapes[3].semiAxis1Pix, 10.0, 1e-4);
  EXPECT_NEAR(shapes[3].semiAxis2Pix, 5.0, 1e-4);
  // North is 30 degrees clockwise from +y, 60 degrees from +x: the width axis (RA) at -30.
  EXPECT_NEAR(shapes[3].angleRad, -30.0 * kRadPerDeg, 1e-6);
}

// On a mirrored image (East to the right of North up) the sky angle turns clockwise: a box at
// sky angle 30 lies at -30 degrees (150 for its width axis) on the pixels.
TEST(Ds9Region, SkyAnglesTurnTheOtherWayOnAMirroredImage) {
  const Cards mirrored = {
      {"CTYPE1", "'RA---TAN'"},  {"CTYPE2", "'DEC--TAN'"},  {"CRPIX1", "200.5"},
      {"CRPIX2", "150.5"},       {"CRVAL1", "150.1"},       {"CRVAL2", "2.2"},
      {"CD1_1", num(kScaleDeg)}, {"CD2_2", num(kScaleDeg)}, {"RADESYS", "'ICRS'"}};
  const auto shapes = parse("fk5; box(150.1,2.2,4\",1\",30)\n", mirrored);
  ASSERT_EQ(shapes.size(), 1U);
  const double c = std::cos(150.0 * kRadPerDeg);
  const double s = std::sin(150.0 * kRadPerDeg);
  EXPECT_TRUE(shapes[0].contains(200.5 + 9.0 * c, 150.5 + 9.0 * s));  // along the width
  EXPECT_FALSE(shapes[0].contains(200.5 + 9.0 * std::cos(30.0 * kRadPerDeg),
                                  150.5 + 9.0 * std::sin(30.0 * kRadPerDeg)));
  // On the unmirrored image (North 60 degrees from +x) a sky angle of 60 gives 60 - 90 + 60.
  const auto unmirrored = parse("fk5; box(150.1,2.2,4\",1\",60)\n", kSkyCards);
  EXPECT_TRUE(unmirrored[0].contains(200.5 + 9.0 * std::cos(30.0 * kRadPerDeg),
                                     150.5 + 9.0 * std::sin(30.0 * kRadPerDeg)));
}

// The writer is the reader's inverse: marks written in fk5 through a rotated and through a
// mirrored WCS, and in image coordinates, read back to the same pixel shapes.
TEST(Ds9Region, WrittenMarksReadBackToTheSamePixelShapes) {
  const Cards mirrored = {
      {"CTYPE1", "'RA---TAN'"},  {"CTYPE2", "'DEC--TAN'"},  {"CRPIX1", "200.5"},
      {"CRPIX2", "150.5"},       {"CRVAL1", "150.1"},       {"CRVAL2", "2.2"},
      {"CD1_1", num(kScaleDeg)}, {"CD2_2", num(kScaleDeg)}, {"RADESYS", "'ICRS'"}};
  std::vector<RegionMark> marks;
  for (int k = 0; k < 6; ++k) {
    RegionMark m;
    m.kind = k % 2 ? RegionShapeKind::Circle : RegionShapeKind::Ellipse;
    m.xCentre = 40.0 + 55.0 * k;
    m.yCentre = 260.0 - 37.0 * k;
    m.semiAxis1Pix = 3.0 + k;
    m.semiAxis2Pix = k % 2 ? m.semiAxis1Pix : 1.5 + 0.5 * k;
    m.angleRad = k % 2 ? 0.0 : (-80.0 + 35.0 * k) * kRadPerDeg;
    m.text = "#" + std::to_string(k + 1) + " {x}";
    marks.push_back(m);
  }
  // A galactic WCS is no fk5 frame: the marks are written in image coordinates.
  Cards galactic = kSkyCards;
  galactic[0].second = "'GLON-TAN'";
  galactic[1].second = "'GLAT-TAN'";
  galactic.pop_back();
  const FitsHeader galacticHeader = makeHeader(galactic);
  const std::optional<Wcs> galacticWcs = Wcs::fromHeader(galacticHeader, "image.fits");
  ASSERT_TRUE(galacticWcs);
  EXPECT_NE(formatDs9Regions(marks, &*galacticWcs).find("\nimage\n"), std::string::npos);
  for (const Cards* cards : {&kSkyCards, &mirrored, static_cast<const Cards*>(nullptr)}) {
    const FitsHeader header = makeHeader(cards ? *cards : Cards{});
    const std::optional<Wcs> wcs = Wcs::fromHeader(header, "image.fits");
    const std::string text = formatDs9Regions(marks, cards ? &*wcs : nullptr);
    EXPECT_NE(text.find(cards ? "\nfk5\n" : "\nimage\n"), std::string::npos);
    EXPECT_NE(text.find("text={#1 x}"), std::string::npos);
    const std::vector<RegionShape> back = parse(text, cards ? *cards : Cards{});
    ASSERT_EQ(back.size(), marks.size());
    for (std::size_t i = 0; i < marks.size(); ++i) {
      SCOPED_TRACE(i);
      EXPECT_NEAR(back[i].xCentre, marks[i].xCentre, 1e-5);
      EXPECT_NEAR(back[i].yCentre, marks[i].yCentre, 1e-5);
      EXPECT_NEAR(back[i].semiAxis1Pix, marks[i].semiAxis1Pix, 1e-6);
      EXPECT_NEAR(back[i].semiAxis2Pix, marks[i].semiAxis2Pix, 1e-6);
      if (marks[i].kind == RegionShapeKind::Ellipse) {
        // An ellipse's angle is defined modulo 180 degrees.
        const double d = std::remainder(back[i].angleRad - marks[i].angleRad, std::numbers::pi);
        EXPECT_NEAR(d, 0.0, 1e-6);
      }
    }
  }
}

// "-00:00:10" is ten arcsec south: the sign of a zero leading field is kept.
TEST(Ds9Region, NegativeDeclinationsBelowOneDegreeKeepTheirSign) {
  const Cards equator = {
      {"CTYPE1", "'RA---TAN'"},   {"CTYPE2", "'DEC--TAN'"},  {"CRPIX1", "200.5"},
      {"CRPIX2", "150.5"},        {"CRVAL1", "150.0"},       {"CRVAL2", "0.0"},
      {"CD1_1", num(-kScaleDeg)}, {"CD2_2", num(kScaleDeg)}, {"RADESYS", "'ICRS'"}};
  const auto shapes = parse(
      "icrs\ncircle(10:00:00,-00:00:10,1\")\ncircle(10h00m00s,-00d00m10s,1\")\n"
      "circle(150,+00:00:10,1\")\ncircle(150,-0.0027777777777777779,1\")\n",
      equator);
  ASSERT_EQ(shapes.size(), 4U);
  EXPECT_NEAR(shapes[0].yCentre, 150.5 - 50.0, 1e-6);
  EXPECT_NEAR(shapes[1].yCentre, 150.5 - 50.0, 1e-6);
  EXPECT_NEAR(shapes[2].yCentre, 150.5 + 50.0, 1e-6);
  EXPECT_NEAR(shapes[3].yCentre, 150.5 - 50.0, 1e-6);
  EXPECT_NEAR(shapes[0].xCentre, 200.5, 1e-6);
}

// Sizes marked i are image pixels and p physical pixels, whatever the shape's system.
TEST(Ds9Region, SizeSuffixesImageAndPhysical) {
  const Cards ltm = {{"LTV1", "0"}, {"LTV2", "0"}, {"LTM1_1", "0.5"}, {"LTM2_2", "0.5"}};
  const auto shapes = parse(
      "physical; circle(10,10,4); circle(10,10,4i)\nimage; circle(5,5,4p); circle(5,5,4)\n", ltm);
  ASSERT_EQ(shapes.size(), 4U);
  EXPECT_DOUBLE_EQ(shapes[0].semiAxis1Pix, 2.0);
  EXPECT_DOUBLE_EQ(shapes[1].semiAxis1Pix, 4.0);
  EXPECT_DOUBLE_EQ(shapes[2].semiAxis1Pix, 2.0);
  EXPECT_DOUBLE_EQ(shapes[3].semiAxis1Pix, 4.0);
}

// Image-coordinate files need no WCS, so broken WCS cards only matter to sky shapes.
TEST(Ds9Region, BrokenWcsCardsOnlyStopSkyShapes) {
  const Cards broken = {{"CTYPE1", "'RA---TAN'"}, {"CTYPE2", "'DEC--TAN'"}, {"CD1_1", "0"},
                        {"CD1_2", "0"},           {"CD2_1", "0"},           {"CD2_2", "0"}};
  EXPECT_EQ(parse("image; circle(1,1,1)\n", broken).size(), 1U);
  EXPECT_THROW(parse("fk5; circle(150,2,1\")\n", broken), ConfigError);
}

TEST(Ds9Region, AreaLessShapesAreSkipped) {
  const auto shapes = parse("image\ntext(5,5) # text={hi}\nline(1,1,5,5)\ncircle(1,1,1)\n");
  ASSERT_EQ(shapes.size(), 1U);
  EXPECT_EQ(shapes[0].lineNumber, 4);
}

// A point masks nothing by itself: without a radius it is refused, never dropped; with one it
// is that circle, in every way DS9 writes it.
TEST(Ds9Region, PointsNeedARadius) {
  test::expectError<ConfigError>([] { parse("image\npoint(10,10) # point=x\n"); },
                                 {"mask.reg:2", "point", "MASK_POINT_RADIUS"});
  test::expectError<ConfigError>([] { parse("image\ncircle point(10,10)\n"); },
                                 {"mask.reg:2", "MASK_POINT_RADIUS"});
  const auto shapes = parse("image\npoint(10,20)\n-box point(30,40)\n", {}, 2.5);
  ASSERT_EQ(shapes.size(), 2U);
  EXPECT_EQ(shapes[0].kind, RegionShapeKind::Circle);
  EXPECT_EQ(shapes[0].xCentre, 10.0);
  EXPECT_EQ(shapes[0].yCentre, 20.0);
  EXPECT_EQ(shapes[0].semiAxis1Pix, 2.5);
  EXPECT_FALSE(shapes[0].exclude);
  EXPECT_TRUE(shapes[1].exclude);
  EXPECT_TRUE(shapes[1].contains(31.5, 41.5));   // 2.12 pixels away
  EXPECT_FALSE(shapes[1].contains(32.0, 42.0));  // 2.83 pixels away
  test::expectError<ConfigError>([] { parse("image\npoint(10)\n", {}, 1.0); },
                                 {"mask.reg:2", "point needs x, y"});
}

TEST(Ds9Region, AnnulusIsTheRingBetweenItsRadii) {
  const auto shapes = parse("image\nannulus(50,60,3,5)\n");
  ASSERT_EQ(shapes.size(), 1U);
  EXPECT_EQ(shapes[0].kind, RegionShapeKind::Annulus);
  EXPECT_FALSE(shapes[0].contains(50.0, 60.0));  // the hole
  EXPECT_FALSE(shapes[0].contains(52.9, 60.0));
  EXPECT_TRUE(shapes[0].contains(53.1, 60.0));
  EXPECT_TRUE(shapes[0].contains(50.0, 55.1));
  EXPECT_FALSE(shapes[0].contains(50.0, 54.9));
  const auto b = shapes[0].bounds();
  EXPECT_EQ(b[0], 45.0);
  EXPECT_EQ(b[1], 55.0);
  EXPECT_EQ(b[2], 55.0);
  EXPECT_EQ(b[3], 65.0);
  test::expectError<ConfigError>([] { parse("image\nannulus(1,1,3,4,5)\n"); },
                                 {"mask.reg:2", "annulus needs", "one annulus"});
  test::expectError<ConfigError>([] { parse("image\nannulus(1,1,5,4)\n"); },
                                 {"mask.reg:2", "inner radius"});
}

TEST(Ds9Region, BadLinesNameTheFileAndLine) {
  test::expectError<ConfigError>([] { parse("image\ncircle(1,1)\n"); },
                                 {"mask.reg:2", "circle needs"});
  test::expectError<ConfigError>([] { parse("image\n\ncircle(1,x,3)\n"); }, {"mask.reg:3", "'x'"});
  test::expectError<ConfigError>([] { parse("image\ncircle 1 1 3\n"); },
                                 {"mask.reg:2", "region shape"});
  test::expectError<ConfigError>([] { parse("image\npanda(1,1,0,360,4,3,4,1)\n"); },
                                 {"mask.reg:2", "panda", "not supported"});
  test::expectError<ConfigError>([] { parse("galactic\ncircle(1,1,3)\n"); },
                                 {"mask.reg:1", "galactic"});
  test::expectError<ConfigError>([] { parse("image; hexagon(1,1,3)\n"); },
                                 {"mask.reg:1", "hexagon"});
  test::expectError<ConfigError>([] { parse("image; circle(1,1,-3)\n"); },
                                 {"mask.reg:1", "negative"});
  test::expectError<ConfigError>([] { parse("image; polygon(1,1,2,2)\n"); },
                                 {"mask.reg:1", "three"});
  test::expectError<ConfigError>([] { parse("image; circle(1,,2,3)\n"); },
                                 {"mask.reg:1", "empty argument"});
  test::expectError<ConfigError>([] { parse("image; circle(1,2,3,)\n"); },
                                 {"mask.reg:1", "empty argument"});
  test::expectError<ConfigError>([] { parse("fk5; circle(10.5:30:00,2.2,3\")\n", kSkyCards); },
                                 {"mask.reg:1", "right ascension"});
  test::expectError<ConfigError>([] { parse("fk5; circle(24:00:01,2.2,3\")\n", kSkyCards); },
                                 {"mask.reg:1", "right ascension"});
  test::expectError<ConfigError>([] { parse("fk5; circle(10:00:24,+02:-12:00,3\")\n", kSkyCards); },
                                 {"mask.reg:1", "declination"});
  test::expectError<ConfigError>([] { parse("fk5; circle(150.1,2.2,3\")\n"); },
                                 {"mask.reg:1", "image.fits", "no celestial WCS"});
  test::expectError<ConfigError>([] { parse("fk5; circle(150.1,95,3\")\n", kSkyCards); },
                                 {"mask.reg:1", "declination"});
  test::expectIoError([] { readDs9Regions("/nonexistent/mask.reg", makeHeader({}), "i.fits"); },
                      {"/nonexistent/mask.reg"});
}

// A region file of random shapes in image and fk5 coordinates, each with a random include or
// exclude sign: every shape's membership and DS9's combined rule at random points agree with
// astropy regions reading the same file.
TEST(Ds9Region, RandomShapesAgreeWithAstropyRegions) {
  if (test::runQuiet("/usr/bin/python3 -c 'import regions'") != 0) {
    OCTARC_SKIP_MISSING()
        << "/usr/bin/python3 with astropy regions (python3-regions) not available";
  }
  const fs::path dir = test::scratchDir();
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> ux(1.0, 400.0);
  std::uniform_real_distribution<double> uy(1.0, 300.0);
  std::uniform_real_distribution<double> size(5.0, 80.0);
  std::uniform_real_distribution<double> angle(-180.0, 360.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::string text = "# Region file format: DS9 version 4.1\nglobal color=green\n";
  const int kShapes = 36;
  const double kPointRadiusPix = 12.5;
  for (int i = 0; i < kShapes; ++i) {
    const bool sky = i % 2 == 1;
    const std::string sign = unit(rng) < 0.3 ? "-" : "";
    // icrs, the frame of the WCS: astropy would move fk5 positions by the FK5 -> ICRS frame bias
    // (about 0.02 arcsec), which octarc ignores as SExtractor's ALPHA_J2000 does.
    std::string line = sky ? "icrs; " : "image; ";
    double x = ux(rng);
    double y = uy(rng);
    // Sky shapes: positions from a pixel through the same linear approximation DS9 users write.
    auto position = [&](double px, double py) {
      if (!sky) return num(px) + "," + num(py);
      const double u = (px - 200.5) * kScaleDeg;
      const double v = (py - 150.5) * kScaleDeg;
      const double xi = -std::cos(kRotationRad) * u + std::sin(kRotationRad) * v;
      const double eta = std::sin(kRotationRad) * u + std::cos(kRotationRad) * v;
      return num(150.1 + xi / std::cos(2.2 * kRadPerDeg)) + "," + num(2.2 + eta);
    };
    auto length = [&](double pixels) { return sky ? num(pixels * 0.2) + "\"" : num(pixels); };
    switch (i % 12 / 2) {
      case 0:
        line += sign + "circle(" + position(x, y) + "," + length(size(rng)) + ")";
        break;
      case 1:
        line += sign + "box(" + position(x, y) + "," + length(size(rng)) + "," + length(size(rng)) +
                "," + num(angle(rng)) + ")";
        break;
      case 2:
        line += sign + "ellipse(" + position(x, y) + "," + length(size(rng)) + "," +
                length(size(rng)) + "," + num(angle(rng)) + ")";
        break;
      case 4: {
        const double inner = size(rng);
        line += sign + "annulus(" + position(x, y) + "," + length(inner) + "," +
                length(inner + size(rng)) + ")";
        break;
      }
      case 5:
        line += sign + "point(" + position(x, y) + ")";  // regions reads no "circle point"
        break;
      default: {
        line += sign + "polygon(";
        const int n = 3 + static_cast<int>(unit(rng) * 5);
        for (int k = 0; k < n; ++k) {
          line += (k ? "," : "") + position(x + size(rng) * std::cos(6.283 * unit(rng)),
                                            y + size(rng) * std::sin(6.283 * unit(rng)));
        }
        line += ")";
      }
    }
    text += line + " # text={shape " + std::to_string(i) + "}\n";
  }
  const auto shapes = parse(text, kSkyCards, kPointRadiusPix);
  ASSERT_EQ(shapes.size(), static_cast<std::size_t>(kShapes));
  { std::ofstream(dir / "random.reg") << text; }

  const int kPoints = 4000;
  std::vector<std::array<double, 2>> points(kPoints);
  {
    std::ofstream out(dir / "points.txt");
    for (auto& p : points) {
      p = {ux(rng), uy(rng)};
      out << num(p[0]) << " " << num(p[1]) << "\n";
    }
  }
  std::string cardsPython = "{";
  for (const auto& [key, value] : kSkyCards) {
    cardsPython += "'" + key + "': " + value + ", ";  // FITS strings are Python strings too
  }
  cardsPython += "'NAXIS': 2, 'NAXIS1': 400, 'NAXIS2': 300}";
  const std::string script =
      "import numpy as np\n"
      "from astropy.wcs import WCS\n"
      "from regions import Regions, PixCoord, SkyRegion, PointPixelRegion, "
      "CirclePixelRegion\n"
      "wcs = WCS(" +
      cardsPython +
      ")\n"
      "xy = np.loadtxt('" +
      (dir / "points.txt").string() +
      "')\n"
      "pix = PixCoord(xy[:, 0] - 1.0, xy[:, 1] - 1.0)\n"  // DS9 image coordinates are 1-based
      "regs = Regions.read('" +
      (dir / "random.reg").string() +
      "', format='ds9')\n"
      "rows = []\n"
      "inc = [r.meta.get('include', 1) != 0 for r in regs]\n"
      "for r in regs:\n"
      "    p = r.to_pixel(wcs) if isinstance(r, SkyRegion) else r\n"
      // regions' points contain nothing: octarc's are circles of the point radius
      "    if isinstance(p, PointPixelRegion):\n"
      "        p = CirclePixelRegion(p.center, " +
      num(kPointRadiusPix) +
      ")\n"
      "    p.meta['include'] = 1\n"  // regions inverts contains() of exclude shapes
      "    rows.append(p.contains(pix))\n"
      "anyinc = any(inc)\n"
      "combined = np.array([(not anyinc or any(rows[k][j] for k in range(len(regs)) if inc[k]))\n"
      "    and not any(rows[k][j] for k in range(len(regs)) if not inc[k])\n"
      "    for j in range(len(xy))])\n"
      "print(' '.join('1' if v else '0' for v in inc))\n"
      "for row in rows + [combined]:\n"
      "    print(''.join('1' if v else '0' for v in row))\n";
  { std::ofstream(dir / "oracle.py") << script; }
  ASSERT_EQ(test::run("/usr/bin/python3 '" + (dir / "oracle.py").string() + "' > '" +
                      (dir / "oracle.txt").string() + "'"),
            0);
  std::ifstream in(dir / "oracle.txt");
  for (int i = 0; i < kShapes; ++i) {
    int include = 0;
    in >> include;
    EXPECT_EQ(include == 0, shapes[i].exclude) << "shape " << i;
  }
  int insideSomewhere = 0;
  for (int i = 0; i <= kShapes; ++i) {
    std::string row;
    in >> row;
    ASSERT_EQ(row.size(), points.size());
    int disagreements = 0;
    for (int j = 0; j < kPoints; ++j) {
      const bool got = i < kShapes ? shapes[i].contains(points[j][0], points[j][1])
                                   : regionContains(shapes, points[j][0], points[j][1]);
      if (got != (row[j] == '1')) ++disagreements;
      if (i < kShapes && got) ++insideSomewhere;
    }
    EXPECT_EQ(disagreements, 0) << (i < kShapes ? "shape " + std::to_string(i) : "combined");
  }
  // The points fall inside shapes often enough for the comparison to mean something (about 2%
  // of point-shape pairs).
  EXPECT_GT(insideSomewhere, 1000);
}

}  // namespace
}  // namespace octarc
