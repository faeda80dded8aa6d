// Point-spread functions and convolution for simulated stamps (METHOD.md section 3).
#pragma once

#include <vector>

#include "octarc/core/Image.h"

namespace octarc::simulation {

// Circular Gaussian PSF, separable: the 1-D kernel k has odd length 2r+1 (r = ceil(5 sigma) in
// pixels, sigma = FWHM / (2 sqrt(2 ln 2))), each tap the Gaussian integrated over its pixel,
// then normalised so that sum k = 1; the 2-D PSF is k_x k_y (sum 1 to rounding).
// Throws ConfigError unless fwhmArcsec > 0 and pixelScaleArcsec > 0.
std::vector<double> gaussianPsfKernel1d(double fwhmArcsec, double pixelScaleArcsec);

// The 2-D image of the same PSF (outer product of the 1-D kernel).
ImageD gaussianPsfImage(double fwhmArcsec, double pixelScaleArcsec);

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
