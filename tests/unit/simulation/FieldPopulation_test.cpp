#include "octarc/simulation/FieldPopulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "LensTestSupport.h"
#include "octarc/io/Wcs.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Seeds.h"

namespace octarc::simulation {
namespace {

TEST(NumberCounts, ExpectedCountIsTheIntegralOfThePowerLaw) {
  // 1000 / deg^2 / mag at m = 21, slope 0.35, 20 < m < 22, 1 deg^2:
  // 1000 (10^0.35 - 10^-0.35) / (0.35 ln 10) = 2223.634 (by hand).
  NumberCounts c{20.0, 22.0, 0.35, 21.0, 1000.0};
  EXPECT_NEAR(c.expectedCount(1.0), 2223.634, 1e-3);
  EXPECT_NEAR(c.expectedCount(0.5), 1111.817, 1e-3);
  // Flat counts: density x range x area.
  NumberCounts flat{20.0, 22.0, 0.0, 21.0, 1000.0};
  EXPECT_NEAR(flat.expectedCount(2.0), 4000.0, 1e-9);
}

// Slope of log10 N between two one-magnitude bins [a, a+1) and [b, b+1).
double countSlope(const std::vector<FieldObject>& objects, FieldObjectKind kind, double a,
                  double b) {
  double na = 0, nb = 0;
  for (const FieldObject& o : objects) {
    if (o.kind != kind) continue;
    if (o.mag >= a && o.mag < a + 1) ++na;
    if (o.mag >= b && o.mag < b + 1) ++nb;
  }
  return std::log10(nb / na) / (b - a);
}

TEST(FieldPopulation, GalaxyAndStarCountsFollowTheirSlopes) {
  FieldPopulationParams p;
  p.stars.densityAtRefPerDeg2PerMag = 2.0e4;  // enough stars for a slope to 0.01
  // 3600 x 3600 pixels of 1" = 1 deg^2.
  std::mt19937_64 rng = systemRng(7, 0);
  const std::vector<FieldObject> objects = drawFieldObjects(p, 3600, 3600, 1.0, rng);
  std::int64_t galaxies = 0, stars = 0;
  for (const FieldObject& o : objects) {
    (o.kind == FieldObjectKind::Star ? stars : galaxies)++;
    ASSERT_GE(o.xPix, -0.5);
    ASSERT_LT(o.xPix, 3599.5);
  }
  // Poisson totals within 5 sigma of the expectations.
  const double expectedGalaxies = p.galaxies.expectedCount(1.0);
  const double expectedStars = p.stars.expectedCount(1.0);
  EXPECT_NEAR(double(galaxies), expectedGalaxies, 5.0 * std::sqrt(expectedGalaxies));
  EXPECT_NEAR(double(stars), expectedStars, 5.0 * std::sqrt(expectedStars));
  // Counts rise 0.35 dex/mag (galaxies) and 0.12 dex/mag (stars); about 1100 galaxies fall in
  // 19-20, so the measured slope is good to ~0.01.
  EXPECT_NEAR(countSlope(objects, FieldObjectKind::Galaxy, 19.0, 24.0), 0.35, 0.015);
  EXPECT_NEAR(countSlope(objects, FieldObjectKind::Star, 15.0, 23.0), 0.12, 0.015);
}

TEST(FieldPopulation, SizesFollowTheMagnitudeSizeRelationAndBrightEllipticalsHaveHaloes) {
  FieldPopulationParams p;
  std::mt19937_64 rng = systemRng(3, 0);
  const std::vector<FieldObject> objects = drawFieldObjects(p, 2000, 2000, 1.0, rng);
  // Median log10 size of faint discs at 25 < m < 25.2: log10(0.45) - 0.1 (25.1 - 22).
  std::vector<double> logSizes;
  int haloes = 0, brightEllipticals = 0;
  for (const FieldObject& o : objects) {
    if (o.kind != FieldObjectKind::Galaxy) continue;
    if (o.type != GalaxyType::Elliptical && o.mag > 25.0 && o.mag < 25.2)
      logSizes.push_back(std::log10(o.halfLightArcsec));
    if (o.type == GalaxyType::Elliptical && o.mag < p.haloMagLimit) ++brightEllipticals;
    if (o.halo) {
      ++haloes;
      EXPECT_EQ(o.type, GalaxyType::Elliptical);
      EXPECT_LT(o.mag, p.haloMagLimit);
    }
  }
  ASSERT_GT(logSizes.size(), 500u);
  std::sort(logSizes.begin(), logSizes.end());
  EXPECT_NEAR(logSizes[logSizes.size() / 2], std::log10(0.45) - 0.1 * 3.1, 0.02);
  EXPECT_GT(haloes, 0);
  EXPECT_EQ(haloes, brightEllipticals);
}

TEST(FieldPopulation, BrightObjectsKeepOutOfTheLensPositions) {
  FieldPopulationParams p;
  std::mt19937_64 rng = systemRng(11, 0);
  const std::vector<Vec2> lenses = {{100.0, 100.0}, {300.0, 250.0}};
  const std::vector<FieldObject> objects =
      drawFieldObjects(p, 400, 400, 1.0, rng, lenses, 40.0, 22.0);
  int near = 0;
  for (const FieldObject& o : objects) {
    for (const Vec2& l : lenses) {
      if (std::hypot(o.xPix - l[0], o.yPix - l[1]) < 40.0) {
        ++near;
        EXPECT_GE(o.mag, 22.0);
      }
    }
  }
  EXPECT_GT(near, 0);  // faint objects may still sit there
}

TEST(GalaxyStamp, SyntheticGalaxyStampHoldsTheFluxOfItsMagnitude) {
  FieldPopulationParams p;
  for (GalaxyType type : {GalaxyType::Spiral, GalaxyType::Irregular}) {
    FieldObject g;
    g.type = type;
    g.mag = 20.0;
    g.halfLightArcsec = 0.8;
    g.xPix = 30.37;
    g.yPix = -2.81;  // partly off an image's edge: the stamp itself is whole
    std::mt19937_64 rng = systemRng(5, int(type));
    double xUsed = 0, yUsed = 0;
    const Stamp s = renderGalaxyStamp(g, p, 0.257, 30.0, rng, &xUsed, &yUsed);
    // 10^(-0.4 (20 - 30)) = 1e4 ADU, exactly (the synthetic stamp is summed in 3x3 blocks).
    EXPECT_NEAR(test::pixelSum(s.pixels), 1.0e4, 1e-6);
    // The centre is placed to a third of a pixel.
    EXPECT_LE(std::abs(xUsed - g.xPix), 1.0 / 6.0 + 1e-9);
    EXPECT_LE(std::abs(yUsed - g.yPix), 1.0 / 6.0 + 1e-9);
    // The same stream gives the same stamp.
    std::mt19937_64 again = systemRng(5, int(type));
    const Stamp t = renderGalaxyStamp(g, p, 0.257, 30.0, again);
    EXPECT_EQ(t.pixels.pixels(), s.pixels.pixels());
    EXPECT_EQ(t.x0, s.x0);
  }
}

TEST(GalaxyStamp, EllipticalStampHoldsTheProfileFluxInsideTheStamp) {
  FieldPopulationParams p;
  FieldObject g;
  g.type = GalaxyType::Elliptical;
  g.mag = 19.0;
  g.halfLightArcsec = 1.0;
  g.axisRatio = 1.0;
  g.xPix = 50.25;
  g.yPix = 40.5;
  std::mt19937_64 rng = systemRng(1, 1);
  for (bool halo : {false, true}) {
    g.halo = halo;
    const Stamp s = renderGalaxyStamp(g, p, 0.257, 30.0, rng);
    const double flux = 1.0e4 * std::pow(10.0, 0.4);  // m = 19 at zero point 30
    const double halfWidthArcsec = 0.5 * double(s.pixels.width() - 1) * 0.257;
    EXPECT_GE(halfWidthArcsec, (halo ? p.haloRadiusInHalfLight : p.stampHalfLightRadii) * 1.0);
    // Between the fractions inside the square's inscribed circle (radius - 1 px for the
    // off-centre position) and its circumscribed circle.
    const double inner = sersicEnclosedFraction(4.0, (halfWidthArcsec - 0.257) / 1.0);
    const double outer = sersicEnclosedFraction(4.0, std::sqrt(2.0) * halfWidthArcsec / 1.0);
    EXPECT_GT(test::pixelSum(s.pixels), flux * inner * (1 - 1e-3));
    EXPECT_LT(test::pixelSum(s.pixels), flux * outer * (1 + 1e-3));
    // Flux-weighted centre on the requested position: the profile is symmetric, but the square
    // cut sits on the nearest pixel, up to half a pixel off, and cuts the wings unevenly.
    double sx = 0, sy = 0, st = 0;
    for (std::int64_t y = 0; y < s.pixels.height(); ++y)
      for (std::int64_t x = 0; x < s.pixels.width(); ++x) {
        st += s.pixels(x, y);
        sx += s.pixels(x, y) * double(x + s.x0);
        sy += s.pixels(x, y) * double(y + s.y0);
      }
    EXPECT_NEAR(sx / st, g.xPix, 0.05);
    EXPECT_NEAR(sy / st, g.yPix, 0.05);
  }
}

TEST(StarStamp, HoldsTheFluxAndIsCentredOnThePosition) {
  const Stamp s = renderStarStamp(20.3, 11.8, 5000.0, 0.9, 0.257, 0.01);
  EXPECT_NEAR(test::pixelSum(s.pixels), 5000.0, 5000.0 * 1e-6);
  double sx = 0, sy = 0;
  for (std::int64_t y = 0; y < s.pixels.height(); ++y)
    for (std::int64_t x = 0; x < s.pixels.width(); ++x) {
      sx += s.pixels(x, y) * double(x + s.x0);
      sy += s.pixels(x, y) * double(y + s.y0);
    }
  EXPECT_NEAR(sx / 5000.0, 20.3, 1e-4);
  EXPECT_NEAR(sy / 5000.0, 11.8, 1e-4);
  // Peak of a centred star: flux x (integral of the unit Gaussian over the central pixel)^2.
  const double sigmaPix = 0.9 / (2.0 * std::sqrt(2.0 * std::log(2.0))) / 0.257;
  const double central = std::erf(0.5 / (sigmaPix * std::sqrt(2.0)));
  const Stamp c = renderStarStamp(10.0, 10.0, 1000.0, 0.9, 0.257, 0.01);
  EXPECT_NEAR(c.pixels(10 - c.x0, 10 - c.y0), 1000.0 * central * central, 1e-9);
}

TEST(StarStamp, BrightStarsAreClippedAtTheSaturationLevel) {
  ImageD field(64, 64);
  // m = 14 at zero point 30: 10^6.4 ADU, peak ~ 1.8e5 ADU.
  addStamp(field, renderStarStamp(31.2, 30.7, fluxFromMagnitude(14.0, 30.0), 0.9, 0.257, 0.01));
  ImageF image(64, 64);
  for (std::int64_t i = 0; i < field.size(); ++i) image[i] = float(field[i]);
  std::int64_t above = 0;
  for (float v : image.pixels()) above += v > 30000.0f;
  ASSERT_GT(above, 4);
  EXPECT_EQ(clipSaturation(image, 30000.0f), above);
  float peak = 0;
  for (float v : image.pixels()) peak = std::max(peak, v);
  EXPECT_EQ(peak, 30000.0f);
  // A faint star stays untouched.
  ImageD faintField(64, 64);
  addStamp(faintField,
           renderStarStamp(31.2, 30.7, fluxFromMagnitude(20.0, 30.0), 0.9, 0.257, 0.01));
  ImageF faint(64, 64);
  for (std::int64_t i = 0; i < faintField.size(); ++i) faint[i] = float(faintField[i]);
  EXPECT_EQ(clipSaturation(faint, 30000.0f), 0);
}

TEST(Stamp, AddStampDropsWhatFallsOutsideTheImage) {
  Stamp s;
  s.pixels = ImageD(4, 3, 1.0);
  s.x0 = -2;  // columns -2, -1 fall off the left edge
  s.y0 = 8;   // row 10 falls off the top of a 10-row image
  ImageD image(5, 10);
  addStamp(image, s);
  EXPECT_DOUBLE_EQ(test::pixelSum(image), 4.0);
  EXPECT_DOUBLE_EQ(image(0, 8), 1.0);
  EXPECT_DOUBLE_EQ(image(1, 9), 1.0);
  EXPECT_DOUBLE_EQ(image(2, 9), 0.0);
}

TEST(FieldWcs, HeaderGivesTheTangentProjectionThroughWcslib) {
  const FitsHeader h = tanWcsHeader(101, 201, 0.257, 150.0, 2.0);
  const std::optional<Wcs> wcs = Wcs::fromHeader(h, "test header");
  ASSERT_TRUE(wcs);
  // CRPIX at the image centre: 1-based (51, 101).
  const auto c = wcs->pixelToWorld(51.0, 101.0);
  EXPECT_NEAR(c[0], 150.0, 1e-10);
  EXPECT_NEAR(c[1], 2.0, 1e-10);
  // Gnomonic projection by hand: (xi, eta) on the tangent plane, in radians,
  // dec = atan2(sin d0 + eta cos d0, sqrt(xi^2 + (cos d0 - eta sin d0)^2)),
  // ra = ra0 + atan2(xi, cos d0 - eta sin d0); north up (+y), east left (-x).
  const double d0 = 2.0 * std::numbers::pi / 180.0;
  const double step = 0.257 / 3600.0 * std::numbers::pi / 180.0;
  for (auto [dx, dy] : {std::pair{0.0, 100.0}, std::pair{-50.0, 0.0}, std::pair{40.0, -90.0}}) {
    const double xi = -dx * step, eta = dy * step;
    const double dec = std::atan2(std::sin(d0) + eta * std::cos(d0),
                                  std::hypot(xi, std::cos(d0) - eta * std::sin(d0)));
    const double ra =
        150.0 * std::numbers::pi / 180.0 + std::atan2(xi, std::cos(d0) - eta * std::sin(d0));
    const auto w = wcs->pixelToWorld(51.0 + dx, 101.0 + dy);
    EXPECT_NEAR(w[0], ra * 180.0 / std::numbers::pi, 1e-10) << dx << " " << dy;
    EXPECT_NEAR(w[1], dec * 180.0 / std::numbers::pi, 1e-10) << dx << " " << dy;
  }
  EXPECT_EQ(wcs->radesys(), "ICRS");
  EXPECT_DOUBLE_EQ(wcs->equinox(), 2000.0);
}

// A round Gaussian source stamp of sigma 0.02" at 0.005"/px.
SourceStamp smallRoundSource() {
  SourceStamp s;
  s.pixelScaleArcsec = 0.005;
  s.fluxPerPixel = ImageD(41, 41);
  for (int y = 0; y < 41; ++y)
    for (int x = 0; x < 41; ++x) {
      const double r2 = (std::pow(x - 20, 2) + std::pow(y - 20, 2)) * 0.005 * 0.005;
      s.fluxPerPixel(x, y) = std::exp(-0.5 * r2 / (0.02 * 0.02));
    }
  s.name = "test source";
  return s;
}

TEST(FieldLensRender, SingularIsothermalSphereGivesItsTwoImagesAndMagnifications) {
  // SIS (eps = 0, no core), b = 1.5", source at beta = 0.5" along +x: images at
  // theta = beta + b = 2.0" (magnification 1 + b/beta = 4) and beta - b = -1.0" (2);
  // total 2 b / beta = 6. The images are narrower than a pixel, so their centroids are exact
  // only with the lens on a pixel centre.
  LensSystem system;
  system.mass.einsteinRadiusArcsec = 1.5;
  system.source.betaArcsec = {0.5, 0.0};
  system.sourceMag = 22.0;
  system.lensMag = 45.0;  // no lens light to speak of
  system.light.halfLightRadiusArcsec = 0.5;
  const double scale = 0.1;
  const FieldLens f = renderFieldLens(system, smallRoundSource(), 100.0, 200.0, scale, 30.0);
  EXPECT_NEAR(f.magnification, 6.0, 0.05);
  ASSERT_EQ(f.images.size(), 2u);
  const auto& outer = f.images[0].xPix > f.images[1].xPix ? f.images[0] : f.images[1];
  const auto& inner = f.images[0].xPix > f.images[1].xPix ? f.images[1] : f.images[0];
  EXPECT_NEAR(outer.xPix, 100.0 + 2.0 / scale, 0.1);
  EXPECT_NEAR(outer.yPix, 200.0, 0.1);
  EXPECT_NEAR(inner.xPix, 100.0 - 1.0 / scale, 0.1);
  EXPECT_NEAR(inner.yPix, 200.0, 0.1);
  // The 2%-of-peak cut leaves out the faint rim of each image (2% of a Gaussian's flux), the
  // same fraction of both, so their flux ratio is tighter than their magnitudes.
  EXPECT_NEAR(outer.mag, 22.0 - 2.5 * std::log10(4.0), 0.04);
  EXPECT_NEAR(inner.mag, 22.0 - 2.5 * std::log10(2.0), 0.04);
  EXPECT_NEAR(inner.mag - outer.mag, 2.5 * std::log10(2.0), 0.01);
  // The stamp holds the lensed flux (the lens light is 1e-6 ADU).
  const double sourceFlux = fluxFromMagnitude(22.0, 30.0);
  EXPECT_NEAR(test::pixelSum(f.stamp.pixels), 6.0 * sourceFlux, 0.05 * sourceFlux);
  // The lens centre sits at (100, 200) in field pixels.
  EXPECT_EQ(f.stamp.x0 + (f.stamp.pixels.width() - 1) / 2, 100);
  EXPECT_EQ(f.stamp.y0 + (f.stamp.pixels.height() - 1) / 2, 200);
}

}  // namespace
}  // namespace octarc::simulation
