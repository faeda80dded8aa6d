// The Gaussian fit of the skewness distributions: exact Gaussian bin values give back their
// parameters, a histogram of normal draws its sigma within the sampling error.
#include "octarc/calibration/GaussianFit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "octarc/calibration/Calibration.h"
#include "octarc/core/Conventions.h"

namespace octarc {
namespace {

TEST(GaussianFit, ExactBinValuesGiveTheirParametersBack) {
  std::vector<double> edges, values;
  for (int k = 0; k <= 40; ++k) edges.push_back(-0.4 + 0.02 * k);
  for (int k = 0; k < 40; ++k) {
    const double x = 0.5 * (edges[k] + edges[k + 1]), u = (x - 0.03) / 0.07;
    values.push_back(0.25 * std::exp(-0.5 * u * u));
  }
  const GaussianFit g = fitGaussian(edges, values);
  EXPECT_TRUE(g.converged);
  EXPECT_NEAR(g.amplitude, 0.25, 1e-7);
  EXPECT_NEAR(g.mean, 0.03, 1e-8);
  EXPECT_NEAR(g.sigma, 0.07, 1e-8);
  EXPECT_NEAR(g.fwhm, 0.07 * 2.0 * std::sqrt(2.0 * std::log(2.0)), 1e-8);
  EXPECT_DOUBLE_EQ(kGaussianFwhmPerSigma, 2.0 * std::sqrt(2.0 * std::log(2.0)));
}

TEST(GaussianFit, AHistogramOfNormalDrawsGivesItsSigma) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(-0.1, 0.2);
  std::vector<double> draws;
  for (int i = 0; i < 200000; ++i) draws.push_back(normal(rng));
  const Histogram h = normalisedHistogram(draws, -1.0, 0.8, 60);
  const GaussianFit g = fitGaussian(h.edges, h.fraction);
  EXPECT_TRUE(g.converged);
  // Bins of w = 0.03 widen the fitted sigma by about w^2/(24 sigma^2) = 0.09 %; N draws scatter
  // it by sigma/sqrt(2N) = 0.16 % and the mean by sigma/sqrt(N). Allowed: three times that
  // scatter about the widened sigma and the true mean.
  const double n = 200000.0, w = 0.03;
  EXPECT_NEAR(g.sigma, 0.2 * (1.0 + w * w / (24 * 0.2 * 0.2)), 3 * 0.2 / std::sqrt(2 * n));
  EXPECT_NEAR(g.mean, -0.1, 3 * 0.2 / std::sqrt(n));
}

TEST(GaussianFit, TooFewBinsGiveNaN) {
  const GaussianFit g = fitGaussian({0.0, 1.0, 2.0, 3.0}, {0.0, 1.0, 0.5});
  EXPECT_FALSE(g.converged);
  EXPECT_TRUE(std::isnan(g.fwhm));
  EXPECT_TRUE(std::isnan(fitGaussian({0.0, 1.0}, {1.0, 2.0}).sigma));  // edges do not match
}

}  // namespace
}  // namespace octarc
