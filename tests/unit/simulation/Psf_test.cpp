#include "octarc/simulation/Psf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc::simulation {
namespace {

// Sum and second moment (pixels^2) of a centred 1-D kernel of odd length.
std::pair<double, double> sumAndSecondMoment(const std::vector<double>& k) {
  double s = 0.0, m2 = 0.0;
  const int r = static_cast<int>(k.size() / 2);
  for (int i = -r; i <= r; ++i) {
    s += k[i + r];
    m2 += k[i + r] * i * i;
  }
  return {s, m2};
}

TEST(GaussianPsf, NormalisedToOneAndHasTheRequestedWidth) {
  for (double fwhm : {0.5, 0.9, 1.7}) {
    const auto k = gaussianPsfKernel1d(fwhm, 0.257, PsfSampling::PixelIntegrated);
    ASSERT_EQ(k.size() % 2, 1u);
    const auto [s, m2] = sumAndSecondMoment(k);
    EXPECT_NEAR(s, 1.0, 1e-12);
    // Pixel-integrated Gaussian: variance sigma^2 + 1/12 px^2.
    const double sigmaPix = fwhm / 0.257 / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    EXPECT_NEAR(m2, sigmaPix * sigmaPix + 1.0 / 12.0, 1e-4 * m2);
    const ImageD psf = gaussianPsfImage(fwhm, 0.257, PsfSampling::PixelIntegrated);
    double s2 = 0.0;
    for (double v : psf.pixels()) s2 += v;
    EXPECT_NEAR(s2, 1.0, 1e-12);
  }
  EXPECT_THROW(gaussianPsfKernel1d(0.0, 0.257, PsfSampling::PointSampled), ConfigError);
}

TEST(GaussianPsf, PointSampledKernelHasTheGaussianVariance) {
  for (double fwhm : {0.5, 0.9, 1.7}) {
    const auto k = gaussianPsfKernel1d(fwhm, 0.257, PsfSampling::PointSampled);
    const auto [s, m2] = sumAndSecondMoment(k);
    EXPECT_NEAR(s, 1.0, 1e-12);
    // No pixel box: the sampled Gaussian keeps its variance (sigma >= 1.3 px here).
    const double sigmaPix = fwhm / 0.257 / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    EXPECT_NEAR(m2, sigmaPix * sigmaPix, 1e-4 * m2);
  }
}

TEST(GaussianSeeing, APixelOfFluxSpreadsWithTheSeeingVarianceAlone) {
  // A flux-per-pixel image through the seeing: variance sigma^2 (no second pixel box), flux kept.
  ImageD img(61, 61);
  img(30, 30) = 3.0;
  const ImageD out = applyGaussianSeeing(img, 0.9, 0.257);
  double sum = 0.0, m2 = 0.0;
  for (std::int64_t y = 0; y < out.height(); ++y) {
    for (std::int64_t x = 0; x < out.width(); ++x) {
      sum += out(x, y);
      m2 += out(x, y) * double((x - 30) * (x - 30));
    }
  }
  const double sigmaPix = 0.9 / 0.257 / (2.0 * std::sqrt(2.0 * std::log(2.0)));
  EXPECT_NEAR(sum, 3.0, 1e-12);
  EXPECT_NEAR(m2 / sum, sigmaPix * sigmaPix, 1e-4 * sigmaPix * sigmaPix);
}

TEST(PsfConvolution, SeparableEqualsDirectAndConservesFlux) {
  ImageD img(41, 39);
  img(20, 19) = 5.0;
  img(9, 30) = 2.0;  // more than the kernel radius (8 px) from each other and the edges
  img(31, 9) = -1.0;
  const auto k = gaussianPsfKernel1d(0.9, 0.257, PsfSampling::PixelIntegrated);
  const ImageD a = convolveSeparable(img, k);
  const ImageD b = convolve(img, gaussianPsfImage(0.9, 0.257, PsfSampling::PixelIntegrated));
  double sa = 0.0;
  for (std::int64_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i], b[i], 1e-12);
    sa += a[i];
  }
  EXPECT_NEAR(sa, 6.0, 1e-12);  // all sources are > 5 sigma from the edges
  // A point convolved with the PSF is the PSF, centred on the point.
  const int r = static_cast<int>(k.size() / 2);
  EXPECT_NEAR(a(20, 19), 5.0 * k[r] * k[r], 1e-12);
  EXPECT_NEAR(a(21, 19), 5.0 * k[r + 1] * k[r], 1e-12);
}

TEST(UserPsf, IsNormalisedAndCentredOnItsMiddlePixel) {
  ImageD psf(5, 5);
  psf(2, 2) = 4.0;
  psf(3, 2) = 4.0;  // asymmetric: flux goes to +x
  const ImageD n = normalisedPsf(psf);
  EXPECT_DOUBLE_EQ(n(2, 2), 0.5);
  ImageD img(9, 9);
  img(4, 4) = 1.0;
  const ImageD out = convolve(img, n);
  EXPECT_DOUBLE_EQ(out(4, 4), 0.5);
  EXPECT_DOUBLE_EQ(out(5, 4), 0.5);
  EXPECT_THROW(normalisedPsf(ImageD(3, 3)), ConfigError);
  ImageD nan(3, 3, 1.0);
  nan(1, 1) = std::nan("");
  EXPECT_THROW(normalisedPsf(nan, "psf.fits"), ConfigError);
}

}  // namespace
}  // namespace octarc::simulation
