#include "octarc/simulation/LensSystem.h"

#include <gtest/gtest.h>

#include <cmath>

#include "LensTestSupport.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/Psf.h"
#include "octarc/simulation/Seeds.h"

namespace octarc::simulation {
namespace {

LensSystem sisSystem(double b, const Vec2& beta) {
  LensSystem sys;
  sys.mass = {b, 0.0, 0.0, 0.0};
  sys.light.halfLightRadiusArcsec = 0.3;
  sys.lensMag = 21.0;
  sys.source.betaArcsec = beta;
  sys.sourceMag = 23.0;
  return sys;
}

TEST(LensSystem, NoiseFreeStampHoldsLensedSourceAndLensLight) {
  ObservingSetup setup;
  setup.addNoise = false;
  setup.rayTrace.fineScaleArcsec = 0.01;
  const double b = 1.5, beta = 0.45;
  const SourceStamp src = test::gaussianSource(0.01, 0.0025, 40, 7.0);
  std::mt19937_64 rng(1);
  const RenderedLensSystem r = renderLensSystem(sisSystem(b, {beta, 0.0}), src, setup, rng);
  // SIS: total magnification 2 b / beta (to 1e-3 for this tiny source).
  EXPECT_NEAR(r.magnification / (2.0 * b / beta), 1.0, 1e-3);
  EXPECT_NEAR(r.lensedSourceFlux, r.magnification * std::pow(10.0, -0.4 * (23.0 - 30.0)), 1e-9);
  // Image flux = lensed source + lens light inside the stamp; the stamp (26" square) holds the
  // de Vaucouleurs profile of r_e = 0.3" between radii 13" and 18.4", and the PSF loses
  // nothing measurable at 13" from the centre.
  const double light = std::pow(10.0, -0.4 * (21.0 - 30.0));
  const double lightMin = light * sersicEnclosedFraction(4.0, 13.0 / 0.3);
  const double lightMax = light * sersicEnclosedFraction(4.0, 18.4 / 0.3);
  const double total = test::pixelSum(r.image);
  EXPECT_GT(total, r.lensedSourceFlux + lightMin - 1e-6 * light);
  EXPECT_LT(total, r.lensedSourceFlux + lightMax + 1e-6 * light);
}

// The ray-traced image already holds the flux falling on each survey pixel, so the stamp of a
// point source is the PSF itself: its FWHM (from the second moments, 2 sqrt(2 ln 2) sigma) must
// be the requested seeing, not the seeing widened by a second pixel box.
TEST(LensSystem, PointSourceStampHasTheRequestedFwhm) {
  for (double fwhmArcsec : {0.9, 0.6, 1.2}) {
    ObservingSetup setup;
    setup.addNoise = false;
    setup.seeingFwhmArcsec = fwhmArcsec;
    // A negligible lens (b = 1e-6") and no lens light: the source as it is, at the stamp centre.
    LensSystem sys = sisSystem(1e-6, {0.0, 0.0});
    sys.lensMag = 99.0;
    const SourceStamp src = test::gaussianSource(0.003, 0.001, 20);
    std::mt19937_64 rng(3);
    const ImageD img = renderLensSystem(sys, src, setup, rng).image;
    double s = 0.0, sx = 0.0, sxx = 0.0;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) {
        s += img(x, y);
        sx += img(x, y) * x;
        sxx += img(x, y) * x * x;
      }
    const double varPix2 = sxx / s - (sx / s) * (sx / s);
    const double measuredFwhmArcsec =
        2.0 * std::sqrt(2.0 * std::log(2.0)) * std::sqrt(varPix2) * setup.grid.pixelScaleArcsec;
    EXPECT_NEAR(measuredFwhmArcsec / fwhmArcsec, 1.0, 0.005) << "FWHM " << fwhmArcsec;
  }
}

TEST(LensSystem, UserPsfImageGivesTheSameStampAsTheSeeing) {
  ObservingSetup gaussian;
  gaussian.addNoise = false;
  const ImageD psf = gaussianPsfImage(0.9, 0.257, PsfSampling::PointSampled);
  ObservingSetup user = gaussian;
  user.userPsf = &psf;
  const SourceStamp src = test::gaussianSource(0.2, 0.03, 30, 7.0);
  std::mt19937_64 rng(2);
  const LensSystem sys = sisSystem(1.2, {0.3, -0.2});
  const ImageD a = renderLensSystem(sys, src, gaussian, rng).image;
  const ImageD b = renderLensSystem(sys, src, user, rng).image;
  for (std::int64_t k = 0; k < a.size(); ++k)
    ASSERT_NEAR(a[k], b[k], 1e-9 * std::abs(a[k]) + 1e-12);
}

TEST(LensSystem, NoiseIsSeededAndHasTheSkySigmaFarFromTheLens) {
  ObservingSetup setup;
  setup.skySigmaAdu = 2.0;
  const SourceStamp src = test::gaussianSource(0.2, 0.03, 30, 7.0);
  const LensSystem sys = sisSystem(1.2, {0.3, -0.2});
  auto r1 = systemRng(9, 4), r2 = systemRng(9, 4);
  const ImageD a = renderLensSystem(sys, src, setup, r1).image;
  const ImageD b = renderLensSystem(sys, src, setup, r2).image;
  EXPECT_EQ(a.pixels(), b.pixels());
  // The outer 20-pixel border (>= 7.7" from the lens) is almost pure sky.
  double s = 0.0, s2 = 0.0;
  int n = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if (std::abs(x - 50) > 30 || std::abs(y - 50) > 30) {
        s += a(x, y);
        s2 += a(x, y) * a(x, y);
        ++n;
      }
  const double var = s2 / n - (s / n) * (s / n);
  EXPECT_NEAR(var / 4.0, 1.0, 5.0 * std::sqrt(2.0 / n));
}

// The second band: with one colour c for the source and the lens the band's stamp is the
// first's scaled by 10^(-0.4 c) (noise free, the PSF is linear); with two colours it is the sum
// of the source alone and the lens alone, each scaled by its own. The first band's stamp and its
// noise draws are those of a render without a second band.
TEST(LensSystem, SecondBandScalesTheSourceAndTheLensByTheirColours) {
  ObservingSetup setup;
  setup.addNoise = false;
  const SourceStamp src = test::gaussianSource(0.2, 0.03, 30);
  const LensSystem sys = sisSystem(1.2, {0.3, -0.2});
  std::mt19937_64 rng(1);
  const SecondBandColours same{0.7, 0.7, nullptr};
  const RenderedLensSystem r = renderLensSystem(sys, src, setup, rng, nullptr, &same);
  ASSERT_EQ(r.bandImage.size(), r.image.size());
  const double scale = std::pow(10.0, -0.4 * 0.7);
  for (std::int64_t k = 0; k < r.image.size(); ++k)
    ASSERT_NEAR(r.bandImage[k], scale * r.image[k], 1e-12 * std::abs(r.image[k]) + 1e-15);

  LensSystem sourceOnly = sys, lensOnly = sys;
  sourceOnly.lensMag = 99.0;
  lensOnly.sourceMag = 99.0;
  const ImageD s = renderLensSystem(sourceOnly, src, setup, rng).image;
  const ImageD l = renderLensSystem(lensOnly, src, setup, rng).image;
  const SecondBandColours two{0.4, 1.2, nullptr};
  const RenderedLensSystem t = renderLensSystem(sys, src, setup, rng, nullptr, &two);
  const double fs = std::pow(10.0, -0.4 * 0.4), fl = std::pow(10.0, -0.4 * 1.2);
  for (std::int64_t k = 0; k < t.image.size(); ++k) {
    const double expected = fs * s[k] + fl * l[k];
    ASSERT_NEAR(t.bandImage[k], expected, 1e-9 * std::abs(expected) + 1e-12);
  }

  setup.addNoise = true;
  auto r1 = systemRng(9, 4), r2 = systemRng(9, 4), bandRng = systemRng(10, 4);
  const SecondBandColours noisy{0.4, 1.2, &bandRng};
  const RenderedLensSystem a = renderLensSystem(sys, src, setup, r1, nullptr, &noisy);
  const ImageD b = renderLensSystem(sys, src, setup, r2).image;
  EXPECT_EQ(a.image.pixels(), b.pixels());
  EXPECT_EQ(r1(), r2());  // the first band's stream is left where it was
  const SecondBandColours noStream{0.4, 1.2, nullptr};
  EXPECT_THROW(renderLensSystem(sys, src, setup, r1, nullptr, &noStream), ConfigError);
}

TEST(LensSystem, UniformPointsInsideTheEinsteinRadius) {
  std::mt19937_64 rng(5);
  const int n = 100000;
  double r2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec2 p = drawUniformInDisc(1.5, rng);
    const double d2 = p[0] * p[0] + p[1] * p[1];
    ASSERT_LE(d2, 2.25);
    r2 += d2;
  }
  // Uniform in area: <r^2> = R^2 / 2, standard deviation of r^2 is R^2 / sqrt(12).
  EXPECT_NEAR(r2 / n, 1.125, 4.0 * 2.25 / std::sqrt(12.0 * n));
}

TEST(LensSystem, RejectsAnEmptySource) {
  SourceStamp dark;
  dark.fluxPerPixel = ImageD(5, 5);
  std::mt19937_64 rng(1);
  EXPECT_THROW(renderLensSystem(sisSystem(1.0, {0, 0}), dark, ObservingSetup{}, rng), ConfigError);
}

}  // namespace
}  // namespace octarc::simulation
