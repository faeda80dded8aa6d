// Point-spread functions and convolution for simulated stamps (METHOD.md section 3).
#pragma once

#include <vector>

#include "octarc/core/Image.h"

namespace octarc::simulation {

// How a kernel tap is taken from the continuous PSF. An image whose pixels already hold the
// flux falling on each pixel (ray-traced stamps, sub-sampled renderings) has had the pixel box
// applied once; convolving it with a pixel-integrated kernel would apply it twice (0.918" for
// 0.9" at 0.257"/px), so such images need the PSF point-sampled at pixel centres.
enum class PsfSampling {
  PixelIntegrated,  // each tap the PSF integrated over its pixel (variance sigma^2 + 1/12 px^2)
  PointSampled,     // each tap the PSF at the pixel centre (variance sigma^2)
};

// Circular Gaussian PSF, separable: the 1-D kernel k has odd length 2r+1 (r = ceil(5 sigma) in
// pixels, sigma = FWHM / (2 sqrt(2 ln 2))), each tap taken as `sampling` says, then normalised
// so that sum k = 1; the 2-D PSF is k_x k_y (sum 1 to rounding).
// Throws ConfigError unless fwhmArcsec > 0 and pixelScaleArcsec > 0.
// No default sampling: each caller says which its image needs.
std::vector<double> gaussianPsfKernel1d(double fwhmArcsec, double pixelScaleArcsec,
                                        PsfSampling sampling);

// The 2-D image of the same PSF (outer product of the 1-D kernel).
ImageD gaussianPsfImage(double fwhmArcsec, double pixelScaleArcsec, PsfSampling sampling);

// Gaussian seeing of FWHM fwhmArcsec applied to an image that already holds the flux per pixel
// (ray-traced stamps, integrated or sub-sampled renderings): the point-sampled kernel, so the
// pixel box is not applied a second time. What the lens and field simulators both use.
ImageD applyGaussianSeeing(const ImageD& fluxPerPixel, double fwhmArcsec, double pixelScaleArcsec);

// A user PSF image, normalised to unit sum. Its centre is pixel (width/2, height/2) (integer
// division, 0-based), i.e. the middle pixel of an odd-sized image. Throws ConfigError naming
// `what` if the image is empty, has non-finite values or a non-positive sum.
ImageD normalisedPsf(const ImageD& psf, const char* what = "PSF image");

// Convolution with a separable kernel (rows, then columns); outside the image counts as zero,
// so flux spread beyond the edges is lost.
ImageD convolveSeparable(const ImageD& image, const std::vector<double>& kernel1d);

// Direct 2-D convolution with a PSF image centred as in normalisedPsf (zero outside).
ImageD convolve(const ImageD& image, const ImageD& psf);

}  // namespace octarc::simulation
