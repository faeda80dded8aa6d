#include "octarc/simulation/Noise.h"

#include <gtest/gtest.h>

#include <cmath>

#include "octarc/core/Error.h"
#include "octarc/simulation/Seeds.h"

namespace octarc::simulation {
namespace {

struct Moments {
  double mean = 0.0;
  double variance = 0.0;
};

Moments moments(const ImageD& img) {
  double s = 0.0, s2 = 0.0;
  for (double v : img.pixels()) s += v;
  const double mean = s / img.size();
  for (double v : img.pixels()) s2 += (v - mean) * (v - mean);
  return {mean, s2 / (img.size() - 1)};
}

// Blank stamp: the noise variance is sigma^2 within its sampling error (relative standard error
// of a variance estimate sqrt(2/N) = 0.35% for N = 160000; we allow 4 standard errors), both in
// the Gaussian regime (DLS-like gain 54) and the exact Poisson regime (few electrons).
TEST(PoissonSkyNoise, BlankStampHasVarianceSigmaSquared) {
  const int n = 400;
  const double relTol = 4.0 * std::sqrt(2.0 / (n * n));
  struct Case {
    double sigma, gain;
  };
  for (const Case c : {Case{3.0, 54.0}, Case{0.5, 4.0}, Case{2.0, 0.25}}) {
    ImageD img(n, n);
    std::mt19937_64 rng(systemSeed(42, 7));
    addPoissonSkyNoise(img, c.sigma, c.gain, rng);
    const Moments m = moments(img);
    EXPECT_NEAR(m.variance / (c.sigma * c.sigma), 1.0, relTol) << c.sigma << " " << c.gain;
    EXPECT_NEAR(m.mean, 0.0, 4.0 * c.sigma / n) << c.sigma << " " << c.gain;
  }
}

TEST(PoissonSkyNoise, SourceFluxAddsItsOwnPoissonVariance) {
  // Signal S ADU per pixel adds S/g to the variance (Poisson on S g electrons).
  const int n = 400;
  const double sigma = 1.0, gain = 2.0, signal = 50.0;
  ImageD img(n, n, signal);
  std::mt19937_64 rng(3);
  addPoissonSkyNoise(img, sigma, gain, rng);
  const Moments m = moments(img);
  EXPECT_NEAR(m.mean, signal, 4.0 * std::sqrt(26.0) / n);
  EXPECT_NEAR(m.variance / (sigma * sigma + signal / gain), 1.0, 4.0 * std::sqrt(2.0) / n);
}

TEST(PoissonSkyNoise, SeededAndReproducible) {
  ImageD a(50, 50), b(50, 50), c(50, 50);
  std::mt19937_64 ra(systemSeed(1, 5)), rb(systemSeed(1, 5)), rc(systemSeed(1, 6));
  addPoissonSkyNoise(a, 2.0, 54.0, ra);
  addPoissonSkyNoise(b, 2.0, 54.0, rb);
  addPoissonSkyNoise(c, 2.0, 54.0, rc);
  EXPECT_EQ(a.pixels(), b.pixels());
  EXPECT_NE(a.pixels(), c.pixels());
  EXPECT_THROW(addPoissonSkyNoise(a, 0.0, 54.0, ra), ConfigError);
  EXPECT_THROW(addPoissonSkyNoise(a, 1.0, -1.0, ra), ConfigError);
}

TEST(SkySigma, FromLimitingMagnitude) {
  // 5 sigma in a 2" aperture at 0.257"/px: N = pi / 0.257^2 = 47.565 px; m = zp gives flux 1.
  const double sigma = skySigmaFromLimitingMagnitude(30.0, 30.0, 2.0, 0.257);
  EXPECT_NEAR(sigma, 1.0 / (5.0 * std::sqrt(3.14159265358979 / (0.257 * 0.257))), 1e-12);
  // One magnitude deeper: 10^-0.4 times the sigma.
  EXPECT_NEAR(skySigmaFromLimitingMagnitude(31.0, 30.0, 2.0, 0.257) / sigma, std::pow(10.0, -0.4),
              1e-12);
}

TEST(SystemSeeds, DistinctPerSystemAndStable) {
  EXPECT_EQ(systemSeed(2026, 0), systemSeed(2026, 0));
  EXPECT_NE(systemSeed(2026, 0), systemSeed(2026, 1));
  EXPECT_NE(systemSeed(2026, 0), systemSeed(2027, 0));
  EXPECT_NE(systemSeed(0, 1), systemSeed(1, 0));
  // splitMix64 reference value (Vigna's splitmix64.c, state 0 -> first output).
  EXPECT_EQ(splitMix64(0), 0xE220A8397B1DCDAFULL);
}

}  // namespace
}  // namespace octarc::simulation
