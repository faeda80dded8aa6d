#include "octarc/simulation/LensLight.h"

#include <gtest/gtest.h>

#include <cmath>

#include "octarc/core/Error.h"

namespace octarc::simulation {
namespace {

TEST(IncompleteGamma, MatchesClosedForms) {
  for (double x : {0.01, 0.5, 2.0, 7.5, 30.0}) {
    EXPECT_NEAR(regularizedGammaP(1.0, x), 1.0 - std::exp(-x), 1e-14);      // P(1,x)
    EXPECT_NEAR(regularizedGammaP(0.5, x), std::erf(std::sqrt(x)), 1e-14);  // P(1/2,x)
    // P(3, x) = 1 - e^-x (1 + x + x^2/2).
    EXPECT_NEAR(regularizedGammaP(3.0, x), 1.0 - std::exp(-x) * (1 + x + x * x / 2), 1e-14);
  }
}

TEST(SersicProfile, BnValues) {
  // b_4 = 7.669249443 (de Vaucouleurs), b_1 = 1.678346990 (exponential), from P(2n, b_n) = 1/2.
  EXPECT_NEAR(sersicBn(4.0), 7.669249443, 1e-8);
  EXPECT_NEAR(sersicBn(1.0), 1.678346990, 1e-8);
  EXPECT_NEAR(sersicEnclosedFraction(4.0, 1.0), 0.5, 1e-12);
  EXPECT_THROW(sersicBn(0.0), ConfigError);
}

TEST(DeVaucouleursLight, HalfLightRadiusEnclosesHalfTheFlux) {
  // r_e = 40 pixels, so the pixelisation of the circle r = r_e costs < 1e-3 of the flux.
  SurveyGrid grid;
  grid.pixelScaleArcsec = 0.05;
  grid.width = grid.height = 501;
  grid.lensXPix = grid.lensYPix = 250.0;
  SersicLightParams p;
  p.halfLightRadiusArcsec = 2.0;
  p.totalFlux = fluxFromMagnitude(21.0, 30.0);
  EXPECT_NEAR(p.totalFlux, std::pow(10.0, 3.6), 1e-9);
  ImageD img(grid.width, grid.height);
  addSersicLight(img, grid, p);
  double inside = 0.0, within5 = 0.0;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const double r = std::hypot(x - 250.0, y - 250.0) * grid.pixelScaleArcsec;
      if (r < 2.0) inside += img(x, y);
      if (r < 10.0) within5 += img(x, y);
    }
  EXPECT_NEAR(inside / p.totalFlux, 0.5, 2e-3);
  EXPECT_NEAR(within5 / p.totalFlux, sersicEnclosedFraction(4.0, 5.0), 2e-3);
}

TEST(DeVaucouleursLight, CompactProfileKeepsItsCuspFlux) {
  // r_e = 0.3" at 0.257"/px (about one pixel), centred off the pixel grid: the stamp of
  // +-40 px holds between the fractions inside 40 px and 40 sqrt(2) px.
  SurveyGrid grid;
  grid.width = grid.height = 81;
  grid.lensXPix = 40.3;
  grid.lensYPix = 39.8;
  const double inner = 39.7 * 0.257 / 0.3, outer = 40.3 * 0.257 * std::sqrt(2.0) / 0.3;
  SersicLightParams p;
  p.halfLightRadiusArcsec = 0.3;
  p.totalFlux = 1.0;
  ImageD img(grid.width, grid.height);
  addSersicLight(img, grid, p);
  double total = 0.0;
  for (double v : img.pixels()) total += v;
  EXPECT_GT(total, sersicEnclosedFraction(4.0, inner) - 1e-4);
  EXPECT_LT(total, sersicEnclosedFraction(4.0, outer) + 1e-4);
}

TEST(DeVaucouleursLight, EllipticalProfileKeepsItsFluxAndOrientation) {
  SurveyGrid grid;
  grid.pixelScaleArcsec = 0.1;
  grid.width = grid.height = 301;
  grid.lensXPix = grid.lensYPix = 150.0;
  SersicLightParams p;
  p.halfLightRadiusArcsec = 0.8;
  p.axisRatio = 0.5;
  p.positionAngleRad = std::numbers::pi / 2;  // major axis along y
  p.totalFlux = 1000.0;
  ImageD img(grid.width, grid.height);
  addSersicLight(img, grid, p);
  double total = 0.0, xx = 0.0, yy = 0.0;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      total += img(x, y);
      xx += img(x, y) * (x - 150.0) * (x - 150.0);
      yy += img(x, y) * (y - 150.0) * (y - 150.0);
    }
  // The stamp spans 15" = 18.75 r_e along the major axis; the flux beyond is < 1%.
  EXPECT_NEAR(total / 1000.0, 1.0, 1e-2);
  EXPECT_GT(total / 1000.0, sersicEnclosedFraction(4.0, 15.0 / 0.8) - 2e-3);
  // Isophotes are ellipses with the major axis along y: 16 px along y is as bright as 8 px along x.
  EXPECT_NEAR(img(150, 166) / img(158, 150), 1.0, 0.02);
  EXPECT_NEAR(img(150, 134) / img(142, 150), 1.0, 0.02);
  EXPECT_GT(yy, 2.0 * xx);
  EXPECT_THROW(addSersicLight(img, grid, {4.0, 1.0, 0.0, 0.0, 1.0}), ConfigError);
}

}  // namespace
}  // namespace octarc::simulation
