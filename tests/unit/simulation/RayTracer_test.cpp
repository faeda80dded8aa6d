#include "octarc/simulation/RayTracer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "LensTestSupport.h"
#include "octarc/core/Error.h"

namespace octarc::simulation {
namespace {

ImageD randomImage(int w, int h, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  ImageD img(w, h);
  for (double& v : img.pixels()) v = u(rng);
  return img;
}

TEST(RebinFluxConserving, HandComputedTwoToThree) {
  // Input 3x1 pixels of 2" -> output 2x1 pixels of 3": output 0 gets all of pixel 0 and half of
  // pixel 1; output 1 the other half of pixel 1 and all of pixel 2.
  ImageD in(3, 1);
  in(0, 0) = 1.0;
  in(1, 0) = 10.0;
  in(2, 0) = 100.0;
  const ImageD out = rebinFluxConserving(in, 2.0, 2, 1, 3.0);
  EXPECT_DOUBLE_EQ(out(0, 0), 6.0);
  EXPECT_DOUBLE_EQ(out(1, 0), 105.0);
}

TEST(RebinFluxConserving, ConservesFluxForIntegerAndNonIntegerRatios) {
  // Fine grids at 0.03"/px covering exactly a grid of survey pixels, for ratios 0.257/0.03
  // (non-integer), 0.12/0.03 (integer) and the reverse direction (coarse to fine).
  {
    const ImageD in = randomImage(257, 171, 1);  // 7.71" x 5.13" = 30 x 19.96 survey px
    const ImageD out = rebinFluxConserving(in, 0.03, 30, 20, 0.257);
    EXPECT_NEAR(test::pixelSum(out) / test::pixelSum(in), 1.0, 1e-6);
  }
  {
    const ImageD in = randomImage(120, 80, 2);
    const ImageD out = rebinFluxConserving(in, 0.03, 30, 20, 0.12);
    EXPECT_NEAR(test::pixelSum(out) / test::pixelSum(in), 1.0, 1e-12);
    double block = 0.0;  // output (0,0) is the sum of the first 4x4 input block
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) block += in(x, y);
    EXPECT_NEAR(out(0, 0), block, 1e-12);
  }
  {
    const ImageD in = randomImage(30, 20, 3);
    const ImageD out = rebinFluxConserving(in, 0.257, 257, 172, 0.03);
    EXPECT_NEAR(test::pixelSum(out) / test::pixelSum(in), 1.0, 1e-6);
  }
  {
    // Only the overlapping part is kept: an output half as wide holds exactly the left half.
    const ImageD in = randomImage(10, 10, 4);
    const ImageD out = rebinFluxConserving(in, 1.0, 2, 4, 2.5);
    double left = 0.0;
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 5; ++x) left += in(x, y);
    EXPECT_NEAR(test::pixelSum(out), left, 1e-10);
  }
}

// A tiny source behind a singular isothermal sphere: the traced flux is the source flux times
// the total magnification |mu+| + |mu-| = (b + beta)/beta + (b - beta)/beta = 2 b / beta,
// averaged over the source: <1/|beta|> = (1/beta0)(1 + sigma^2 / (2 beta0^2)) to second order for
// a circular Gaussian of width sigma (the 2-D Laplacian of 1/r is 1/r^3).
TEST(TraceLensedImage, TinySourceThroughSisHasAnalyticMagnification) {
  const double b = 1.5;
  const double sigma = 0.01;
  const EllipticalPotentialLens sis({b, 0.0, 0.0, 0.0});
  const SourceStamp source = test::gaussianSource(sigma, 0.0025, 40);
  SurveyGrid grid;  // 101 x 101 px of 0.257" (26"), lens at the centre
  RayTraceOptions options;
  options.fineScaleArcsec = 0.01;  // rays every 0.0025", four per source sigma
  for (double betaOverB : {0.2, 0.35, 0.5}) {
    const double beta0 = betaOverB * b;
    SourcePlacement place;
    place.betaArcsec = {beta0 * 0.6, beta0 * 0.8};
    RayTraceStats stats;
    const ImageD img = traceLensedImage(sis, source, place, grid, options, &stats);
    const double expected = 2.0 * b / beta0 * (1.0 + sigma * sigma / (2.0 * beta0 * beta0));
    EXPECT_NEAR(test::pixelSum(img) / expected, 1.0, 1e-3) << "beta/b " << betaOverB;
    EXPECT_GT(stats.finePixelsSkipped, stats.finePixelsTotal * 9 / 10);  // tiny source
  }
}

// A tiny source near the centre of the elliptical potential (theta_c = 0) has four images; the
// traced flux equals the sum of |mu| at the image positions found by solving the lens equation.
TEST(TraceLensedImage, TinySourceThroughEllipticalPotentialHasFourImageMagnification) {
  const double b = 1.4, eps = 0.12;
  const EllipticalPotentialLens lens({b, eps, 0.0, 0.5});
  const Vec2 beta0{0.06, -0.04};
  // Start from the analytic images of a source at the origin, in the rotated lens frame.
  const double c = std::cos(0.5), s = std::sin(0.5);
  const double r1 = b * std::sqrt(1.0 - eps), r2 = b * std::sqrt(1.0 + eps);
  const Vec2 starts[4] = {
      {r1 * c, r1 * s}, {-r1 * c, -r1 * s}, {-r2 * s, r2 * c}, {r2 * s, -r2 * c}};
  double sumAbsMu = 0.0;
  Vec2 images[4];
  for (int i = 0; i < 4; ++i) {
    images[i] = test::solveLensEquation(lens, starts[i], beta0);
    const Vec2 back = lens.sourcePositionArcsec(images[i]);
    ASSERT_NEAR(back[0], beta0[0], 1e-12);
    ASSERT_NEAR(back[1], beta0[1], 1e-12);
    sumAbsMu += std::abs(lens.magnification(images[i]));
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < i; ++j)
      ASSERT_GT(std::hypot(images[i][0] - images[j][0], images[i][1] - images[j][1]), 0.1);
  const SourceStamp source = test::gaussianSource(0.005, 0.00125, 40);
  RayTraceOptions options;
  options.fineScaleArcsec = 0.005;
  SourcePlacement place;
  place.betaArcsec = beta0;
  const ImageD img = traceLensedImage(lens, source, place, SurveyGrid{}, options);
  EXPECT_NEAR(test::pixelSum(img) / sumAbsMu, 1.0, 3e-3) << "sum |mu| = " << sumAbsMu;
}

TEST(TraceLensedImage, SkippingUnreachablePixelsChangesNothing) {
  const EllipticalPotentialLens lens({1.3, 0.15, 0.02, 0.4});
  const SourceStamp source = test::gaussianSource(0.15, 0.03, 25);
  SourcePlacement place;
  place.betaArcsec = {0.2, -0.1};
  place.rotationRad = 0.3;
  SurveyGrid grid;
  grid.width = 41;
  grid.height = 37;
  grid.lensXPix = 20.3;
  grid.lensYPix = 17.6;
  RayTraceOptions all;
  all.skipUnreachable = false;
  RayTraceStats fastStats, allStats;
  const ImageD fast = traceLensedImage(lens, source, place, grid, {}, &fastStats);
  const ImageD slow = traceLensedImage(lens, source, place, grid, all, &allStats);
  EXPECT_EQ(allStats.finePixelsSkipped, 0);
  EXPECT_GT(fastStats.finePixelsSkipped, fastStats.finePixelsTotal / 2);
  for (std::int64_t k = 0; k < fast.size(); ++k) ASSERT_EQ(fast[k], slow[k]) << "pixel " << k;
}

TEST(TraceLensedImage, NegligibleLensReproducesTheSource) {
  // With b -> 0 the image is the source itself: flux conserved, centroid at the source position.
  const EllipticalPotentialLens lens({1e-9, 0.0, 0.0, 0.0});
  const SourceStamp source = test::gaussianSource(0.3, 0.03, 60);
  SourcePlacement place;
  place.betaArcsec = {1.0, -0.5};
  SurveyGrid grid;
  const ImageD img = traceLensedImage(lens, source, place, grid);
  EXPECT_NEAR(test::pixelSum(img), 1.0, 1e-4);
  double sx = 0.0, sy = 0.0;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      sx += img(x, y) * (x - grid.lensXPix);
      sy += img(x, y) * (y - grid.lensYPix);
    }
  EXPECT_NEAR(sx / test::pixelSum(img) * grid.pixelScaleArcsec, 1.0, 2e-3);
  EXPECT_NEAR(sy / test::pixelSum(img) * grid.pixelScaleArcsec, -0.5, 2e-3);

  // Resizing through the placement scale: a source twice as large keeps its flux.
  place.pixelScaleArcsec = 0.06;
  EXPECT_NEAR(test::pixelSum(traceLensedImage(lens, source, place, grid)), 1.0, 1e-4);
}

TEST(TraceLensedImage, RotationTurnsAnElongatedSource) {
  // A bar along the stamp's x axis, rotated by 90 degrees, lies along the sky's y axis.
  SourceStamp bar;
  bar.pixelScaleArcsec = 0.03;
  bar.fluxPerPixel = ImageD(81, 81);
  for (int x = 10; x <= 70; ++x) bar.fluxPerPixel(x, 40) = 1.0;
  const EllipticalPotentialLens lens({1e-9, 0.0, 0.0, 0.0});
  SourcePlacement place;
  place.rotationRad = std::numbers::pi / 2;
  SurveyGrid grid;
  grid.width = grid.height = 31;
  grid.lensXPix = grid.lensYPix = 15.0;
  const ImageD img = traceLensedImage(lens, bar, place, grid);
  double xx = 0.0, yy = 0.0;
  for (int y = 0; y < 31; ++y)
    for (int x = 0; x < 31; ++x) {
      xx += img(x, y) * (x - 15.0) * (x - 15.0);
      yy += img(x, y) * (y - 15.0) * (y - 15.0);
    }
  EXPECT_GT(yy, 10.0 * xx);
}

TEST(TraceLensedImage, RejectsBadOptions) {
  const EllipticalPotentialLens lens({1.0, 0.0, 0.0, 0.0});
  const SourceStamp source = test::gaussianSource(0.1, 0.03, 10);
  RayTraceOptions bad;
  bad.subSamples = 0;
  EXPECT_THROW(traceLensedImage(lens, source, {}, {}, bad), ConfigError);
  SourceStamp empty;
  EXPECT_THROW(traceLensedImage(lens, empty, {}, {}), ConfigError);
  EXPECT_THROW(rebinFluxConserving(ImageD(2, 2), 0.0, 1, 1, 1.0), ConfigError);
}

}  // namespace
}  // namespace octarc::simulation
