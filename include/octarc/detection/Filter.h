// The detection filter: SExtractor's FILTER/FILTER_NAME (.conv kernels).
#pragma once

#include <vector>

#include "octarc/core/Image.h"

namespace octarc {

// A convolution mask as read from a .conv file, already normalised as the file asks.
struct ConvKernel {
  int width = 0;                     // columns (odd in every SExtractor kernel)
  int height = 0;                    // rows
  std::vector<float> coefficients;   // row-major, height rows of width values, first row = first line
};

// The filtered image SExtractor thresholds: the kernel applied as a correlation centred on each
// pixel, with zero padding outside the image and no renormalisation at the edges. NaN pixels
// count as zero for their neighbours and stay NaN themselves.
ImageF applyFilter(const ImageF& image, const ConvKernel& kernel);

}  // namespace octarc
