#include "octarc/background/GlobalBackground.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "BackgroundTestSupport.h"
#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

ImageF fromValues(std::initializer_list<float> values) {
  ImageF image(static_cast<std::int64_t>(values.size()), 1);
  std::int64_t i = 0;
  for (float v : values) image[i++] = v;
  return image;
}

// Iterated kappa-sigma clipping of a normal distribution converges to the sigma s with
// s^2 = sigma^2 g(kappa s / sigma), g(c) = 1 - 2 c phi(c) / (2 Phi(c) - 1): the variance of a
// normal truncated at +-c. Returns s / sigma.
double clippedGaussianSigmaRatio(double kappa) {
  double r = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double c = kappa * r;
    const double phi = std::exp(-0.5 * c * c) / std::sqrt(2.0 * std::numbers::pi);
    const double inside = std::erf(c / std::sqrt(2.0));
    r = std::sqrt(1.0 - 2.0 * c * phi / inside);
  }
  return r;
}

TEST(GlobalBackground, HandComputedClipping) {
  // {1,2,3,4,100}: median 3, mean 22, sigma sqrt(1522) = 39.01. With kappa 1.5 the 100 goes
  // (|100-3| > 58.5); then {1,2,3,4}: mean = median = 2.5, sigma sqrt(1.25), range
  // 2.5 +- 1.68 keeps all four, so the second step confirms convergence.
  const GlobalBackground g = estimateGlobalBackground(fromValues({4, 100, 1, 3, 2}), 1.5);
  EXPECT_EQ(g.pixelCount, 4);
  EXPECT_DOUBLE_EQ(g.meanAdu, 2.5);
  EXPECT_DOUBLE_EQ(g.medianAdu, 2.5);
  EXPECT_DOUBLE_EQ(g.sigmaAdu, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(g.levelAdu, 2.5);
  EXPECT_EQ(g.iterations, 2);
  EXPECT_TRUE(g.converged);

  // kappa 100 clips nothing: |mean - median| = 19 > 0.3 sigma, so the level is the median.
  const GlobalBackground wide = estimateGlobalBackground(fromValues({4, 100, 1, 3, 2}), 100.0);
  EXPECT_EQ(wide.pixelCount, 5);
  EXPECT_DOUBLE_EQ(wide.meanAdu, 22.0);
  EXPECT_DOUBLE_EQ(wide.medianAdu, 3.0);
  EXPECT_NEAR(wide.sigmaAdu, std::sqrt(1522.0), 1e-12);
  EXPECT_DOUBLE_EQ(wide.levelAdu, 3.0);

  // Zero iterations: statistics of all valid pixels.
  const GlobalBackground none = estimateGlobalBackground(fromValues({4, 100, 1, 3, 2}), 1.5, 0);
  EXPECT_EQ(none.pixelCount, 5);
  EXPECT_FALSE(none.converged);
}

TEST(GlobalBackground, NonFinitePixelsAreIgnored) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const GlobalBackground g =
      estimateGlobalBackground(fromValues({nan, 4, 100, inf, 1, -inf, 3, 2, -1e31f}), 1.5);
  EXPECT_EQ(g.pixelCount, 4);
  EXPECT_DOUBLE_EQ(g.medianAdu, 2.5);
  EXPECT_DOUBLE_EQ(g.sigmaAdu, std::sqrt(1.25));
}

TEST(GlobalBackground, GaussianNoiseRecoversMeanAndSigma) {
  const double sky = 100.0, sigma = 5.0;
  const ImageF image = test::skyWithGradient(1000, 1000, sky, 0.0, 0.0, sigma, 2024);
  const GlobalBackground g = estimateGlobalBackground(image);
  const double n = static_cast<double>(image.size());
  // Standard errors for N = 10^6: mean sigma/sqrt(N) = 0.005; standard deviation about
  // sigma/sqrt(2N) = 0.0035; the mode 2.5 median - 1.5 mean about 2 sigma/sqrt(N) = 0.01.
  EXPECT_TRUE(g.converged);
  EXPECT_NEAR(g.meanAdu, sky, 5 * sigma / std::sqrt(n));
  EXPECT_NEAR(g.medianAdu, sky, 5 * 1.26 * sigma / std::sqrt(n));
  EXPECT_NEAR(g.levelAdu, sky, 5 * 2.0 * sigma / std::sqrt(n));
  const double expectedSigma = clippedGaussianSigmaRatio(3.0) * sigma;  // 0.9733 sigma
  EXPECT_NEAR(g.sigmaAdu, expectedSigma, 5 * sigma / std::sqrt(2 * n));
  EXPECT_GT(g.pixelCount, static_cast<std::int64_t>(0.99 * n));
  EXPECT_TRUE(g.warning.empty());
}

TEST(GlobalBackground, SourcesBarelyMoveTheClippedSigma) {
  const double sky = 100.0, sigma = 5.0;
  ImageF image = test::skyWithGradient(1000, 1000, sky, 0.0, 0.0, sigma, 77);
  const GlobalBackground clean = estimateGlobalBackground(image);
  test::addSources(image, 500, 20000.0, 78);  // about 1 source per 2000 pixels
  const GlobalBackground g = estimateGlobalBackground(image);
  std::printf("  with sources: level %.4f sigma %.4f (noise only: %.4f, %.4f)\n", g.levelAdu,
              g.sigmaAdu, clean.levelAdu, clean.sigmaAdu);
  EXPECT_NEAR(g.sigmaAdu, clean.sigmaAdu, 0.03 * sigma);
  EXPECT_NEAR(g.levelAdu, sky, 0.05 * sigma);
  // Without clipping the sources dominate the standard deviation.
  const GlobalBackground raw = estimateGlobalBackground(image, 3.0, 0);
  EXPECT_GT(raw.sigmaAdu, 2 * sigma);
}

TEST(GlobalBackground, MatchesAstropySigmaClippedStats) {
  if (!test::haveProgram("/usr/bin/python3") ||
      test::runQuiet("/usr/bin/python3 -c 'import astropy.stats'") != 0)
    OCTARC_SKIP_MISSING() << "astropy not available";
  ImageF image = test::skyWithGradient(600, 500, 1000.0, 0.0, 0.0, 8.0, 5);
  test::addSources(image, 800, 30000.0, 6);
  image(3, 4) = std::numeric_limits<float>::quiet_NaN();
  const fs::path dir = test::scratchDir();
  test::writeFloatFits(dir / "clip.fits", image);
  const std::string cmd = "/usr/bin/python3 '" + std::string(OCTARC_SOURCE_DIR) +
                          "/tests/unit/background/astropy_sigma_clip.py' '" +
                          (dir / "clip.fits").string() + "' 3 2>/dev/null";
  std::string output;
  ASSERT_EQ(test::runCommand(cmd, &output), 0) << cmd;
  ASSERT_FALSE(output.empty());
  std::istringstream in(output);
  double mean = 0, median = 0, std = 0;
  in >> mean >> median >> std;
  const GlobalBackground g = estimateGlobalBackground(image, 3.0);
  // Reached: the same doubles to all 17 printed digits. The median is a pixel value (or the mean
  // of two), exact; the mean and the standard deviation are sums taken in another order than
  // numpy's pairwise summation, so a few ulps are allowed (EXPECT_DOUBLE_EQ: 4 ulps).
  EXPECT_DOUBLE_EQ(g.meanAdu, mean);
  EXPECT_EQ(g.medianAdu, median);
  EXPECT_DOUBLE_EQ(g.sigmaAdu, std);
}

TEST(GlobalBackground, ConstantImageWarnsAndUsesUnitSigma) {
  const GlobalBackground g = estimateGlobalBackground(ImageF(64, 64, 12.5f), 3.0, 100, "c.fits");
  EXPECT_EQ(g.levelAdu, 12.5);
  EXPECT_EQ(g.sigmaAdu, 1.0);
  EXPECT_NE(g.warning.find("c.fits"), std::string::npos);
  EXPECT_NE(g.warning.find("constant"), std::string::npos);
}

TEST(GlobalBackground, AllNanIsAnError) {
  const ImageF image(20, 20, std::numeric_limits<float>::quiet_NaN());
  try {
    (void)estimateGlobalBackground(image, 3.0, 100, "nan.fits");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("nan.fits: no valid pixels"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  EXPECT_THROW((void)estimateGlobalBackground(ImageF(), 3.0), IoError);
  EXPECT_THROW((void)estimateGlobalBackground(ImageF(2, 2, 1.0f), 0.0), ConfigError);
  EXPECT_THROW((void)estimateGlobalBackground(ImageF(2, 2, 1.0f), 3.0, -1), ConfigError);
}

TEST(GlobalBackground, ResultsDoNotDependOnThreadCount) {
  ImageF image = test::skyWithGradient(700, 300, 50.0, 0.0, 0.0, 2.0, 31);
  test::addSources(image, 300, 1000.0, 32);
  const GlobalBackground one = estimateGlobalBackground(image, 3.0, 100, "x", 1);
  const GlobalBackground two = estimateGlobalBackground(image, 3.0, 100, "x", 2);
  const GlobalBackground seven = estimateGlobalBackground(image, 3.0, 100, "x", 7);
  EXPECT_EQ(one.levelAdu, two.levelAdu);
  EXPECT_EQ(one.sigmaAdu, two.sigmaAdu);
  EXPECT_EQ(one.meanAdu, seven.meanAdu);
  EXPECT_EQ(one.medianAdu, seven.medianAdu);
  EXPECT_EQ(one.pixelCount, seven.pixelCount);
}

}  // namespace
}  // namespace octarc
