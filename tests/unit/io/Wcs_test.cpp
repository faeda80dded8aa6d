#include "octarc/io/Wcs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "FitsHeaders.h"
#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsImage.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

std::string numberText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.15G", v);
  return text;
}

// An 800 x 600 image with these cards.
FitsHeader wcsHeader(const test::Cards& cards) {
  return test::imageHeader(800, 600, cards);
}

// A rotated, flipped CD matrix (degrees per pixel) shared by the projection tests.
constexpr double kCd11 = -2.0e-4 * 0.8660254037844386;
constexpr double kCd12 = 2.0e-4 * 0.5;
constexpr double kCd21 = 2.0e-4 * 0.5;
constexpr double kCd22 = 2.0e-4 * 0.8660254037844386;
constexpr double kCrpix1 = 400.5;
constexpr double kCrpix2 = 300.25;
constexpr double kRa0Deg = 150.1;
constexpr double kDec0Deg = 2.2;

std::vector<std::pair<std::string, std::string>> linearCards(const std::string& projection) {
  return {{"CTYPE1", quoteFitsString("RA---" + projection)},
          {"CTYPE2", quoteFitsString("DEC--" + projection)},
          {"CRPIX1", numberText(kCrpix1)},
          {"CRPIX2", numberText(kCrpix2)},
          {"CRVAL1", numberText(kRa0Deg)},
          {"CRVAL2", numberText(kDec0Deg)},
          {"CD1_1", numberText(kCd11)},
          {"CD1_2", numberText(kCd12)},
          {"CD2_1", numberText(kCd21)},
          {"CD2_2", numberText(kCd22)}};
}

// Intermediate world coordinates (degrees) of a 1-based pixel offset from CRPIX.
std::array<double, 2> cdTimes(double u, double v) {
  return {kCd11 * u + kCd12 * v, kCd21 * u + kCd22 * v};
}

// Inverse gnomonic projection about (kRa0Deg, kDec0Deg) of standard coordinates in degrees.
std::array<double, 2> gnomonic(double xiDeg, double etaDeg) {
  const double xi = xiDeg * kRadPerDeg;
  const double eta = etaDeg * kRadPerDeg;
  const double dec0 = kDec0Deg * kRadPerDeg;
  const double denom = std::cos(dec0) - eta * std::sin(dec0);
  const double ra = kRa0Deg * kRadPerDeg + std::atan2(xi, denom);
  const double dec = std::atan2(std::sin(dec0) + eta * std::cos(dec0), std::hypot(xi, denom));
  return {ra * kDegPerRad, dec * kDegPerRad};
}

// Inverse orthographic (SIN without PV terms) projection about (kRa0Deg, kDec0Deg).
std::array<double, 2> orthographic(double xiDeg, double etaDeg) {
  const double xi = xiDeg * kRadPerDeg;
  const double eta = etaDeg * kRadPerDeg;
  const double dec0 = kDec0Deg * kRadPerDeg;
  const double rootTerm = std::sqrt(1.0 - xi * xi - eta * eta);
  const double ra =
      kRa0Deg * kRadPerDeg + std::atan2(xi, std::cos(dec0) * rootTerm - eta * std::sin(dec0));
  const double dec = std::asin(eta * std::cos(dec0) + std::sin(dec0) * rootTerm);
  return {ra * kDegPerRad, dec * kDegPerRad};
}

// 1e-9 degrees is 3.6 micro-arcseconds: far below any astrometric need, far above roundoff.
constexpr double kTolDeg = 1e-9;

const std::vector<std::array<double, 2>> kPixels = {
    {kCrpix1, kCrpix2}, {1.0, 1.0}, {800.0, 600.0}, {37.25, 580.5}, {799.0, 2.0}, {400.0, 1.0}};

void expectWorld(const std::array<double, 2>& got, const std::array<double, 2>& want) {
  EXPECT_NEAR(got[0], want[0], kTolDeg);
  EXPECT_NEAR(got[1], want[1], kTolDeg);
}

TEST(Wcs, TanMatchesClosedFormGnomonic) {
  const auto wcs = Wcs::fromHeader(wcsHeader(linearCards("TAN")), "tan.fits");
  ASSERT_TRUE(wcs.has_value());
  for (const auto& p : kPixels) {
    SCOPED_TRACE(std::to_string(p[0]) + "," + std::to_string(p[1]));
    const auto xy = cdTimes(p[0] - kCrpix1, p[1] - kCrpix2);
    expectWorld(wcs->pixelToWorld(p[0], p[1]), gnomonic(xy[0], xy[1]));
  }
  // CRPIX maps exactly to CRVAL.
  expectWorld(wcs->pixelToWorld(kCrpix1, kCrpix2), {kRa0Deg, kDec0Deg});
}

// Found by fuzzing: wcslib's header parser overflows a buffer on a string value that never
// closes, and the process aborts. Such cards are left out, as if absent.
TEST(Wcs, CardsWcslibCannotParseAreLeftOut) {
  FitsHeader h = wcsHeader(linearCards("TAN"));
  for (std::string& card : h.cards) {
    if (card.rfind("CTYPE2", 0) == 0) {
      card = std::string("CTYPE2  = 'DEC-CD1_1   =").append(55, ' ');
    }
  }
  // Without its CTYPE2 the WCS has one celestial axis: an error naming the file, no abort.
  EXPECT_THROW(Wcs::fromHeader(h, "unterminated.fits"), IoError);
  // A card with a NUL is left out too; the rest of the WCS stays.
  FitsHeader n = wcsHeader(linearCards("TAN"));
  n.cards.push_back(std::string("COMMENT x").append(1, '\0').append(70, ' '));
  const auto withNul = Wcs::fromHeader(n, "nul.fits");
  ASSERT_TRUE(withNul.has_value());
  expectWorld(withNul->pixelToWorld(kCrpix1, kCrpix2), {kRa0Deg, kDec0Deg});
}

TEST(Wcs, SinMatchesClosedFormOrthographic) {
  const auto wcs = Wcs::fromHeader(wcsHeader(linearCards("SIN")), "sin.fits");
  ASSERT_TRUE(wcs.has_value());
  for (const auto& p : kPixels) {
    const auto xy = cdTimes(p[0] - kCrpix1, p[1] - kCrpix2);
    expectWorld(wcs->pixelToWorld(p[0], p[1]), orthographic(xy[0], xy[1]));
  }
}

// SIP: pixel offsets (u, v) from CRPIX are distorted by polynomials before the CD matrix.
constexpr double kA20 = 2.0e-6, kA11 = -1.5e-6, kA02 = 3.0e-7, kA30 = 1.0e-9;
constexpr double kB20 = -4.0e-7, kB11 = 2.5e-6, kB02 = 1.2e-6, kB03 = -2.0e-9;

FitsHeader sipHeader() {
  auto cards = linearCards("TAN-SIP");
  const std::vector<std::pair<std::string, std::string>> sip = {{"A_ORDER", "3"},
                                                                {"B_ORDER", "3"},
                                                                {"A_2_0", numberText(kA20)},
                                                                {"A_1_1", numberText(kA11)},
                                                                {"A_0_2", numberText(kA02)},
                                                                {"A_3_0", numberText(kA30)},
                                                                {"B_2_0", numberText(kB20)},
                                                                {"B_1_1", numberText(kB11)},
                                                                {"B_0_2", numberText(kB02)},
                                                                {"B_0_3", numberText(kB03)}};
  cards.insert(cards.end(), sip.begin(), sip.end());
  return wcsHeader(cards);
}

TEST(Wcs, SipMatchesHandComputedPolynomialPlusTan) {
  const auto wcs = Wcs::fromHeader(sipHeader(), "sip.fits");
  ASSERT_TRUE(wcs.has_value());
  for (const auto& p : kPixels) {
    SCOPED_TRACE(std::to_string(p[0]) + "," + std::to_string(p[1]));
    const double u = p[0] - kCrpix1;
    const double v = p[1] - kCrpix2;
    const double f = kA20 * u * u + kA11 * u * v + kA02 * v * v + kA30 * u * u * u;
    const double g = kB20 * u * u + kB11 * u * v + kB02 * v * v + kB03 * v * v * v;
    const auto xy = cdTimes(u + f, v + g);
    expectWorld(wcs->pixelToWorld(p[0], p[1]), gnomonic(xy[0], xy[1]));
  }
  // The distortion is real: at the corner it moves the position by far more than the tolerance.
  const auto plain = Wcs::fromHeader(wcsHeader(linearCards("TAN")), "tan.fits");
  EXPECT_GT(std::fabs(wcs->pixelToWorld(1, 1)[0] - plain->pixelToWorld(1, 1)[0]), 1e-5);
}

// TPV: polynomials in the intermediate world coordinates (degrees) after the CD matrix.
constexpr double kPv1_0 = 1.0e-5, kPv1_4 = 0.8, kPv1_7 = 25.0;  // xi: x^2 and x^3 terms
constexpr double kPv2_5 = -0.6, kPv2_3 = 0.01;                  // eta: y x and r terms

FitsHeader tpvHeader() {
  auto cards = linearCards("TPV");
  const std::vector<std::pair<std::string, std::string>> pv = {
      {"PV1_0", numberText(kPv1_0)}, {"PV1_1", "1.0"}, {"PV1_4", numberText(kPv1_4)},
      {"PV1_7", numberText(kPv1_7)}, {"PV2_1", "1.0"}, {"PV2_3", numberText(kPv2_3)},
      {"PV2_5", numberText(kPv2_5)}};
  cards.insert(cards.end(), pv.begin(), pv.end());
  return wcsHeader(cards);
}

TEST(Wcs, TpvMatchesHandComputedPolynomialPlusTan) {
  const auto wcs = Wcs::fromHeader(tpvHeader(), "tpv.fits");
  ASSERT_TRUE(wcs.has_value());
  for (const auto& p : kPixels) {
    SCOPED_TRACE(std::to_string(p[0]) + "," + std::to_string(p[1]));
    const auto xy = cdTimes(p[0] - kCrpix1, p[1] - kCrpix2);
    const double x = xy[0];
    const double y = xy[1];
    const double r = std::hypot(x, y);
    const double xi = kPv1_0 + x + kPv1_4 * x * x + kPv1_7 * x * x * x;
    const double eta = y + kPv2_3 * r + kPv2_5 * y * x;
    expectWorld(wcs->pixelToWorld(p[0], p[1]), gnomonic(xi, eta));
  }
  const auto plain = Wcs::fromHeader(wcsHeader(linearCards("TAN")), "tan.fits");
  EXPECT_GT(std::fabs(wcs->pixelToWorld(1, 1)[1] - plain->pixelToWorld(1, 1)[1]), 1e-5);
}

// Many positions in one call: each exactly as alone (batches of more than one transform call),
// and a position the projection cannot take gives NaN for itself only.
TEST(Wcs, PixelsToWorldEqualsOneByOne) {
  const auto wcs = Wcs::fromHeader(sipHeader(), "sip.fits");
  ASSERT_TRUE(wcs.has_value());
  std::vector<double> pixels;
  for (int i = 0; i < 21; ++i) {
    pixels.push_back(1.0 + 37.25 * i);
    pixels.push_back(500.0 - 11.5 * i);
  }
  std::vector<double> world(pixels.size());
  wcs->pixelsToWorld(pixels.data(), 21, world.data());
  for (int i = 0; i < 21; ++i) {
    const auto one = wcs->pixelToWorld(pixels[2 * i], pixels[2 * i + 1]);
    EXPECT_EQ(world[2 * i], one[0]) << i;
    EXPECT_EQ(world[2 * i + 1], one[1]) << i;
  }
  // SIN: pixels beyond the projection's limb have no world position.
  const auto sin = Wcs::fromHeader(wcsHeader(linearCards("SIN")), "sin.fits");
  ASSERT_TRUE(sin.has_value());
  const double mixed[6] = {kCrpix1, kCrpix2, kCrpix1 + 1e7, kCrpix2, kCrpix1 + 3.0, kCrpix2};
  double out[6];
  sin->pixelsToWorld(mixed, 3, out);
  EXPECT_EQ(out[0], sin->pixelToWorld(kCrpix1, kCrpix2)[0]);
  EXPECT_TRUE(std::isnan(out[2]) && std::isnan(out[3]));
  EXPECT_TRUE(std::isnan(sin->pixelToWorld(kCrpix1 + 1e7, kCrpix2)[0]));
  EXPECT_EQ(out[4], sin->pixelToWorld(kCrpix1 + 3.0, kCrpix2)[0]);
  EXPECT_EQ(out[5], sin->pixelToWorld(kCrpix1 + 3.0, kCrpix2)[1]);
}

TEST(Wcs, WorldToPixelInvertsPixelToWorld) {
  for (const FitsHeader& h :
       {wcsHeader(linearCards("TAN")), wcsHeader(linearCards("SIN")), sipHeader(), tpvHeader()}) {
    const auto wcs = Wcs::fromHeader(h, "roundtrip.fits");
    ASSERT_TRUE(wcs.has_value());
    for (const auto& p : kPixels) {
      const auto world = wcs->pixelToWorld(p[0], p[1]);
      const auto back = wcs->worldToPixel(world[0], world[1]);
      EXPECT_NEAR(back[0], p[0], 1e-6) << *h.value("CTYPE1");
      EXPECT_NEAR(back[1], p[1], 1e-6) << *h.value("CTYPE1");
    }
  }
}

TEST(Wcs, CopiesAndMovesKeepTheTransform) {
  const auto wcs = Wcs::fromHeader(sipHeader(), "sip.fits");
  ASSERT_TRUE(wcs.has_value());
  const auto want = wcs->pixelToWorld(10.0, 20.0);
  Wcs copy = *wcs;
  EXPECT_EQ(copy.pixelToWorld(10.0, 20.0), want);
  Wcs moved = std::move(copy);
  EXPECT_EQ(moved.pixelToWorld(10.0, 20.0), want);
  Wcs assigned = *Wcs::fromHeader(wcsHeader(linearCards("TAN")), "tan.fits");
  assigned = moved;
  EXPECT_EQ(assigned.pixelToWorld(10.0, 20.0), want);
}

TEST(Wcs, ConcurrentCallsGiveTheSameResults) {
  const auto wcs = Wcs::fromHeader(tpvHeader(), "tpv.fits");
  ASSERT_TRUE(wcs.has_value());
  std::vector<std::array<double, 2>> want;
  for (int i = 0; i < 500; ++i) want.push_back(wcs->pixelToWorld(1.0 + i, 600.0 - i));
  std::vector<int> mismatches(4, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int round = 0; round < 20; ++round) {
        for (int i = 0; i < 500; ++i) {
          if (wcs->pixelToWorld(1.0 + i, 600.0 - i) != want[i]) ++mismatches[t];
          wcs->worldToPixel(want[i][0], want[i][1]);
        }
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int m : mismatches) EXPECT_EQ(m, 0);
}

TEST(Wcs, HeaderWithoutCelestialAxesGivesNullopt) {
  EXPECT_FALSE(Wcs::fromHeader(wcsHeader({}), "plain.fits").has_value());
  EXPECT_FALSE(Wcs::fromHeader(FitsHeader{}, "empty.fits").has_value());
  // Linear axes only (as in many old headers: blank CTYPEs with CDELT/CRVAL).
  EXPECT_FALSE(Wcs::fromHeader(wcsHeader({{"CTYPE1", "'        '"},
                                          {"CTYPE2", "'        '"},
                                          {"CRPIX1", "1.0"},
                                          {"CDELT1", "1.0"}}),
                               "linear.fits")
                   .has_value());
  EXPECT_FALSE(
      Wcs::fromHeader(wcsHeader({{"CTYPE1", "'WAVE'"}, {"CTYPE2", "'TIME'"}}), "spectral.fits")
          .has_value());
}

TEST(Wcs, BrokenWcsGivesIoErrorNamingTheFile) {
  auto badProjection = linearCards("TAN");
  badProjection[0].second = "'RA---QQQ'";
  badProjection[1].second = "'DEC--QQQ'";
  auto singular = linearCards("TAN");
  for (auto& [key, value] : singular) {
    if (key.rfind("CD", 0) == 0) value = "0.0";
  }
  for (const auto& cards : {badProjection, singular}) {
    try {
      Wcs::fromHeader(wcsHeader(cards), "broken.fits");
      ADD_FAILURE() << "no IoError";
    } catch (const IoError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("broken.fits: ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

TEST(Wcs, DegenerateThirdAxisIsDropped) {
  auto cards = linearCards("TAN");
  cards.push_back({"NAXIS", "3"});
  cards.push_back({"NAXIS3", "1"});
  cards.push_back({"CTYPE3", "'FREQ'"});
  cards.push_back({"CRVAL3", "1.4E9"});
  cards.push_back({"CRPIX3", "1"});
  cards.push_back({"CDELT3", "1E6"});
  const auto wcs = Wcs::fromHeader(wcsHeader(cards), "cube.fits");
  ASSERT_TRUE(wcs.has_value());
  const auto xy = cdTimes(37.25 - kCrpix1, 580.5 - kCrpix2);
  expectWorld(wcs->pixelToWorld(37.25, 580.5), gnomonic(xy[0], xy[1]));
}

TEST(Wcs, EquinoxAndRadesysFollowFitsDefaults) {
  auto withFrame = [](std::vector<std::pair<std::string, std::string>> extra) {
    auto cards = linearCards("TAN");
    cards.insert(cards.end(), extra.begin(), extra.end());
    return *Wcs::fromHeader(wcsHeader(cards), "frame.fits");
  };
  EXPECT_EQ(withFrame({}).radesys(), "ICRS");
  EXPECT_EQ(withFrame({}).equinox(), 2000.0);
  EXPECT_EQ(withFrame({{"EQUINOX", "2000.0"}}).radesys(), "FK5");
  EXPECT_EQ(withFrame({{"EQUINOX", "1950.0"}}).radesys(), "FK4");
  EXPECT_EQ(withFrame({{"EQUINOX", "1950.0"}}).equinox(), 1950.0);
  EXPECT_EQ(withFrame({{"RADESYS", "'FK4'"}}).equinox(), 1950.0);
  EXPECT_EQ(withFrame({{"RADESYS", "'FK5'"}, {"EQUINOX", "2010.5"}}).equinox(), 2010.5);
  EXPECT_EQ(withFrame({{"EPOCH", "1975.0"}, {"RADESYS", "'FK5'"}}).equinox(), 1975.0);
}

TEST(Wcs, PixelToJ2000LeavesIcrsAndJ2000Unchanged) {
  for (const auto& extra : std::vector<std::vector<std::pair<std::string, std::string>>>{
           {}, {{"RADESYS", "'ICRS'"}}, {{"RADESYS", "'FK5'"}, {"EQUINOX", "2000.0"}}}) {
    auto cards = linearCards("TAN");
    cards.insert(cards.end(), extra.begin(), extra.end());
    const auto wcs = Wcs::fromHeader(wcsHeader(cards), "j2000.fits");
    EXPECT_EQ(wcs->pixelToJ2000(12.0, 34.0), wcs->pixelToWorld(12.0, 34.0));
    const auto world = wcs->pixelToWorld(12.0, 34.0);
    EXPECT_EQ(wcs->worldToJ2000(world[0], world[1]), wcs->pixelToJ2000(12.0, 34.0));
  }
  auto ecliptic = linearCards("TAN");
  ecliptic[0].second = "'ELON-TAN'";
  ecliptic[1].second = "'ELAT-TAN'";
  const auto ecl = Wcs::fromHeader(wcsHeader(ecliptic), "ecl.fits");
  ASSERT_TRUE(ecl.has_value());
  EXPECT_TRUE(std::isnan(ecl->pixelToJ2000(12.0, 34.0)[0]));
}

// Galactic headers: ALPHA/DELTA_J2000 through the rotation of the IAU galactic system, compared
// with astropy's Galactic -> FK5(J2000) (the definitions agree to a few milliarcseconds).
TEST(Wcs, PixelToJ2000RotatesGalacticLikeAstropy) {
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path dir = test::scratchDir();
  std::string script =
      "from astropy.coordinates import SkyCoord, FK5\n"
      "import astropy.units as u\n";
  const double lb[4][2] = {{0.0, 0.0}, {150.1, 2.2}, {280.5, -63.0}, {33.0, 85.0}};
  for (const auto& p : lb) {
    script += "c = SkyCoord(l=" + numberText(p[0]) + "*u.deg, b=" + numberText(p[1]) +
              "*u.deg, frame='galactic').transform_to(FK5(equinox='J2000'))\n"
              "print(repr(c.ra.deg), repr(c.dec.deg))\n";
  }
  { std::ofstream(dir / "gal.py") << script; }
  ASSERT_EQ(test::run("/usr/bin/python3 '" + (dir / "gal.py").string() + "' > '" +
                      (dir / "gal.txt").string() + "'"),
            0);
  std::ifstream in(dir / "gal.txt");
  for (const auto& p : lb) {
    SCOPED_TRACE(std::to_string(p[0]) + "," + std::to_string(p[1]));
    const auto wcs = Wcs::fromHeader(wcsHeader({{"CTYPE1", "'GLON-TAN'"},
                                                {"CTYPE2", "'GLAT-TAN'"},
                                                {"CRPIX1", "1.0"},
                                                {"CRPIX2", "1.0"},
                                                {"CRVAL1", numberText(p[0])},
                                                {"CRVAL2", numberText(p[1])},
                                                {"CDELT1", "-1E-4"},
                                                {"CDELT2", "1E-4"}}),
                                     "gal.fits");
    ASSERT_TRUE(wcs.has_value());
    double ra = 0.0;
    double dec = 0.0;
    in >> ra >> dec;
    const auto got = wcs->pixelToJ2000(1.0, 1.0);
    const double sepArcsec =
        std::hypot((got[0] - ra) * std::cos(dec * kRadPerDeg), got[1] - dec) * 3600.0;
    EXPECT_LT(sepArcsec, 0.05);
  }
}

// Meeus, Astronomical Algorithms (2nd ed.), example 21.b: theta Persei, mean place of
// J2000.0 (41.054063, +49.227750) precessed with the IAU 1976 angles to the mean equinox of
// JD 2462088.69 gives 2h46m11.331s, +49d20'54.54". Precessing that back must recover J2000.
TEST(Wcs, PixelToJ2000PrecessesFk5WithIau1976) {
  const double jd = 2462088.69;
  const double equinoxYears = 2000.0 + (jd - 2451545.0) / 365.25;
  const double raDateDeg = (2.0 + 46.0 / 60.0 + 11.331 / 3600.0) * 15.0;
  const double decDateDeg = 49.0 + 20.0 / 60.0 + 54.54 / 3600.0;
  const auto wcs = Wcs::fromHeader(wcsHeader({{"CTYPE1", "'RA---TAN'"},
                                              {"CTYPE2", "'DEC--TAN'"},
                                              {"CRPIX1", "1.0"},
                                              {"CRPIX2", "1.0"},
                                              {"CRVAL1", numberText(raDateDeg)},
                                              {"CRVAL2", numberText(decDateDeg)},
                                              {"CDELT1", "-1E-4"},
                                              {"CDELT2", "1E-4"},
                                              {"RADESYS", "'FK5'"},
                                              {"EQUINOX", numberText(equinoxYears)}}),
                                   "meeus.fits");
  ASSERT_TRUE(wcs.has_value());
  const auto j2000 = wcs->pixelToJ2000(1.0, 1.0);
  // The published values are rounded to 0.001 s and 0.01": 2e-5 deg covers that.
  EXPECT_NEAR(j2000[0], 41.054063, 2e-5);
  EXPECT_NEAR(j2000[1], 49.227750, 2e-5);
}

// An FK5 B1950-like header against astropy's FK5 -> FK5(J2000) transformation. astropy uses
// the newer IAU 2006 precession; over 50 years the two models differ by about 0.1 arcsec.
TEST(Wcs, PixelToJ2000AgreesWithAstropyFk5) {
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path dir = test::scratchDir();
  auto cards = linearCards("TAN");
  cards.push_back({"RADESYS", "'FK5'"});
  cards.push_back({"EQUINOX", "1950.0"});
  const auto wcs = Wcs::fromHeader(wcsHeader(cards), "fk5.fits");
  ASSERT_TRUE(wcs.has_value());
  const std::array<double, 2> pix[] = {{1.0, 1.0}, {800.0, 600.0}};
  std::string script =
      "from astropy.coordinates import SkyCoord, FK5\n"
      "import astropy.units as u\n";
  for (const auto& p : pix) {
    const auto w = wcs->pixelToWorld(p[0], p[1]);
    script += "c = SkyCoord(" + numberText(w[0]) + "*u.deg, " + numberText(w[1]) +
              "*u.deg, frame=FK5(equinox='J1950')).transform_to(FK5(equinox='J2000'))\n"
              "print(repr(c.ra.deg), repr(c.dec.deg))\n";
  }
  { std::ofstream(dir / "fk5.py") << script; }
  ASSERT_EQ(test::run("/usr/bin/python3 '" + (dir / "fk5.py").string() + "' > '" +
                      (dir / "fk5.txt").string() + "'"),
            0);
  std::ifstream in(dir / "fk5.txt");
  for (const auto& p : pix) {
    double ra = 0.0;
    double dec = 0.0;
    in >> ra >> dec;
    const auto got = wcs->pixelToJ2000(p[0], p[1]);
    EXPECT_NEAR(got[0], ra, 0.3 / 3600.0);
    EXPECT_NEAR(got[1], dec, 0.3 / 3600.0);
    // Precession over 50 years is about 0.6 degrees in RA here: the test is not vacuous.
    EXPECT_GT(std::fabs(got[0] - wcs->pixelToWorld(p[0], p[1])[0]), 0.3);
  }
}

// FK4 (B1950) headers are only precessed (no E-terms, no FK4 -> FK5 rotation): against
// astropy's full FK4 -> FK5 conversion the documented error stays below about 1 arcsec.
TEST(Wcs, PixelToJ2000Fk4IsPrecessedWithinOneArcsecond) {
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path dir = test::scratchDir();
  auto cards = linearCards("TAN");
  cards.push_back({"EQUINOX", "1950.0"});  // FK4 by the FITS default for EQUINOX < 1984
  const auto wcs = Wcs::fromHeader(wcsHeader(cards), "fk4.fits");
  ASSERT_TRUE(wcs.has_value());
  ASSERT_EQ(wcs->radesys(), "FK4");
  const auto w = wcs->pixelToWorld(kCrpix1, kCrpix2);
  const std::string script =
      "from astropy.coordinates import SkyCoord, FK4, FK5\n"
      "import astropy.units as u\n"
      "c = SkyCoord(" +
      numberText(w[0]) + "*u.deg, " + numberText(w[1]) +
      "*u.deg, frame=FK4(equinox='B1950', obstime='B1950')).transform_to(FK5(equinox='J2000'))\n"
      "print(repr(c.ra.deg), repr(c.dec.deg))\n";
  { std::ofstream(dir / "fk4.py") << script; }
  ASSERT_EQ(test::run("/usr/bin/python3 '" + (dir / "fk4.py").string() + "' > '" +
                      (dir / "fk4.txt").string() + "'"),
            0);
  std::ifstream in(dir / "fk4.txt");
  double ra = 0.0;
  double dec = 0.0;
  in >> ra >> dec;
  const auto got = wcs->pixelToJ2000(kCrpix1, kCrpix2);
  const double cosDec = std::cos(dec * kRadPerDeg);
  const double sepArcsec = std::hypot((got[0] - ra) * cosDec, got[1] - dec) * 3600.0;
  EXPECT_LT(sepArcsec, 1.0);
  EXPECT_GT(std::fabs(got[0] - w[0]), 0.3);  // precessed, not returned unchanged
}

TEST(Wcs, RealNttHeaderHasNoCelestialWcsLikeAstropy) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path image = shared / "ntt-emmi" / "galaxies.fits";
  const fs::path dir = test::scratchDir();
  // astropy sees only linear axes (blank CTYPEs, CDELT 1, CRVAL 1 at CRPIX 1): with origin=1
  // world equals the 1-based pixel, and there is no celestial part.
  const std::string script =
      "import warnings\n"
      "from astropy.io import fits\n"
      "from astropy.wcs import WCS\n"
      "warnings.simplefilter('ignore')\n"
      "w = WCS(fits.getheader('" +
      image.string() +
      "'))\n"
      "print(int(w.has_celestial))\n"
      "for x, y in [(1, 1), (512.5, 100.25), (1024, 1024)]:\n"
      "    wx, wy = w.all_pix2world([[x, y]], 1)[0]\n"
      "    print(repr(wx), repr(wy))\n";
  { std::ofstream(dir / "wcs.py") << script; }
  ASSERT_EQ(test::run("/usr/bin/python3 '" + (dir / "wcs.py").string() + "' > '" +
                      (dir / "wcs.txt").string() + "'"),
            0);
  std::ifstream in(dir / "wcs.txt");
  int hasCelestial = -1;
  in >> hasCelestial;
  EXPECT_EQ(hasCelestial, 0);
  const double pix[3][2] = {{1, 1}, {512.5, 100.25}, {1024, 1024}};
  for (const auto& p : pix) {
    double wx = 0.0;
    double wy = 0.0;
    in >> wx >> wy;
    EXPECT_DOUBLE_EQ(wx, p[0]);
    EXPECT_DOUBLE_EQ(wy, p[1]);
  }
  const ImageHdu hdu = readImageHeader(image.string());
  EXPECT_FALSE(Wcs::fromHeader(hdu.header, image.string()).has_value());
}

// The same SIP header through astropy (all_pix2world, origin=1) and through octarc.
TEST(Wcs, SipAgreesWithAstropy) {
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path dir = test::scratchDir();
  const FitsHeader header = sipHeader();
  ImageF pixels(800, 600, 0.0f);
  const fs::path fits = dir / "sip.fits";
  writeImageFile(fits.string(), {{header, &pixels, nullptr}});
  const std::string script =
      "import warnings\n"
      "from astropy.io import fits\n"
      "from astropy.wcs import WCS\n"
      "warnings.simplefilter('ignore')\n"
      "w = WCS(fits.getheader('" +
      fits.string() +
      "'))\n"
      "for x, y in [(1, 1), (800, 600), (37.25, 580.5)]:\n"
      "    wx, wy = w.all_pix2world([[x, y]], 1)[0]\n"
      "    print(repr(wx), repr(wy))\n";
  { std::ofstream(dir / "sip.py") << script; }
  ASSERT_EQ(test::run("/usr/bin/python3 '" + (dir / "sip.py").string() + "' > '" +
                      (dir / "sip.txt").string() + "'"),
            0);
  std::ifstream in(dir / "sip.txt");
  const auto wcs = Wcs::fromHeader(readImageHeader(fits.string()).header, fits.string());
  ASSERT_TRUE(wcs.has_value());
  const double pix[3][2] = {{1, 1}, {800, 600}, {37.25, 580.5}};
  for (const auto& p : pix) {
    double wx = 0.0;
    double wy = 0.0;
    in >> wx >> wy;
    const auto got = wcs->pixelToWorld(p[0], p[1]);
    EXPECT_NEAR(got[0], wx, kTolDeg);
    EXPECT_NEAR(got[1], wy, kTolDeg);
  }
}

}  // namespace
}  // namespace octarc
