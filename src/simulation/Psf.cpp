#include "octarc/simulation/Psf.h"

#include <cmath>
#include <string>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc::simulation {

std::vector<double> gaussianPsfKernel1d(double fwhmArcsec, double pixelScaleArcsec,
                                        PsfSampling sampling) {
  if (!(fwhmArcsec > 0.0) || !(pixelScaleArcsec > 0.0))
    throw ConfigError("PSF: FWHM and pixel scale must be positive, got FWHM " +
                      std::to_string(fwhmArcsec) + "\", scale " + std::to_string(pixelScaleArcsec) +
                      "\"/px");
  const double sigmaPix = fwhmArcsec / pixelScaleArcsec / kGaussianFwhmPerSigma;
  const int radius = static_cast<int>(std::ceil(5.0 * sigmaPix));
  std::vector<double> kernel(2 * radius + 1);
  const double scale = 1.0 / (std::sqrt(2.0) * sigmaPix);
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    // Integral of the unit Gaussian over pixel [i - 1/2, i + 1/2], or its value at i (the
    // normalisation below takes care of the constant factor).
    const double v = sampling == PsfSampling::PixelIntegrated
                         ? 0.5 * (std::erf((i + 0.5) * scale) - std::erf((i - 0.5) * scale))
                         : std::exp(-(i * scale) * (i * scale));
    kernel[i + radius] = v;
    sum += v;
  }
  for (double& v : kernel) v /= sum;
  return kernel;
}

ImageD gaussianPsfImage(double fwhmArcsec, double pixelScaleArcsec, PsfSampling sampling) {
  const std::vector<double> k = gaussianPsfKernel1d(fwhmArcsec, pixelScaleArcsec, sampling);
  const auto n = static_cast<std::int64_t>(k.size());
  ImageD psf(n, n);
  for (std::int64_t y = 0; y < n; ++y)
    for (std::int64_t x = 0; x < n; ++x) psf(x, y) = k[x] * k[y];
  return psf;
}

ImageD applyGaussianSeeing(const ImageD& fluxPerPixel, double fwhmArcsec, double pixelScaleArcsec) {
  return convolveSeparable(
      fluxPerPixel, gaussianPsfKernel1d(fwhmArcsec, pixelScaleArcsec, PsfSampling::PointSampled));
}

ImageD normalisedPsf(const ImageD& psf, const char* what) {
  if (psf.empty()) throw ConfigError(std::string(what) + ": PSF image is empty");
  double sum = 0.0;
  for (double v : psf.pixels()) {
    if (!std::isfinite(v)) throw ConfigError(std::string(what) + ": PSF has non-finite pixels");
    sum += v;
  }
  if (!(sum > 0.0))
    throw ConfigError(std::string(what) + ": PSF sum must be positive, got " + std::to_string(sum));
  ImageD out = psf;
  for (double& v : out.pixels()) v /= sum;
  return out;
}

ImageD convolveSeparable(const ImageD& image, const std::vector<double>& kernel1d) {
  const auto w = image.width();
  const auto h = image.height();
  const auto r = static_cast<std::int64_t>(kernel1d.size() / 2);
  ImageD rows(w, h);
  for (std::int64_t y = 0; y < h; ++y)
    for (std::int64_t x = 0; x < w; ++x) {
      const double v = image(x, y);
      if (v == 0.0) continue;
      // Scatter: out(x + k - r) += v * kernel[k] (a symmetric kernel makes this a convolution).
      const std::int64_t kLo = std::max<std::int64_t>(0, r - x);
      const std::int64_t kHi = std::min<std::int64_t>(2 * r, w - 1 - x + r);
      for (std::int64_t k = kLo; k <= kHi; ++k) rows(x + k - r, y) += v * kernel1d[k];
    }
  ImageD out(w, h);
  for (std::int64_t y = 0; y < h; ++y) {
    const std::int64_t kLo = std::max<std::int64_t>(0, r - y);
    const std::int64_t kHi = std::min<std::int64_t>(2 * r, h - 1 - y + r);
    for (std::int64_t k = kLo; k <= kHi; ++k) {
      const double kv = kernel1d[k];
      const std::int64_t yo = y + k - r;
      for (std::int64_t x = 0; x < w; ++x) out(x, yo) += kv * rows(x, y);
    }
  }
  return out;
}

ImageD convolve(const ImageD& image, const ImageD& psf) {
  const auto w = image.width();
  const auto h = image.height();
  const auto cx = psf.width() / 2;
  const auto cy = psf.height() / 2;
  ImageD out(w, h);
  for (std::int64_t y = 0; y < h; ++y)
    for (std::int64_t x = 0; x < w; ++x) {
      const double v = image(x, y);
      if (v == 0.0) continue;
      for (std::int64_t py = 0; py < psf.height(); ++py) {
        const std::int64_t yo = y + py - cy;
        if (yo < 0 || yo >= h) continue;
        for (std::int64_t px = 0; px < psf.width(); ++px) {
          const std::int64_t xo = x + px - cx;
          if (xo >= 0 && xo < w) out(xo, yo) += v * psf(px, py);
        }
      }
    }
  return out;
}

}  // namespace octarc::simulation
