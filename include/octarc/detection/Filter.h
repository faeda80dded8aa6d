// The detection filter: SExtractor's FILTER/FILTER_NAME (.conv kernels).
#pragma once

#include <vector>

#include "octarc/core/ConvKernel.h"
#include "octarc/core/Image.h"

namespace octarc {

// The filtered image SExtractor thresholds: the kernel applied as a correlation centred on each
// pixel, with zero padding outside the image and no renormalisation at the edges:
//   out(x, y) = sum_j sum_i coefficients[j * width + i] * in(x + i - width/2, y + j - height/2),
// so the first .conv line weights the row below the pixel (smaller y), as in source-extractor.
// Non-finite pixels (NaN, +-Inf) count as zero for their neighbours and keep their own value.
// Throws ConfigError if the kernel is empty or its size and coefficient count disagree.
// `threads` row bands are filtered in parallel (<= 0: all hardware threads); the result does
// not depend on it.
ImageF applyFilter(const ImageF& image, const ConvKernel& kernel, int threads = 1);

}  // namespace octarc
