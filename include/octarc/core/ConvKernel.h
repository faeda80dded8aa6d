// A detection filter's convolution mask (SExtractor's FILTER_NAME .conv file), as a value that
// every stage may hold: sextractor_compat reads it, the detection filter applies it, the
// simulations keep it in their setup.
#pragma once

#include <vector>

namespace octarc {

// A convolution mask as read from a .conv file, already normalised as the file asks.
struct ConvKernel {
  int width = 0;   // columns (odd in every SExtractor kernel)
  int height = 0;  // rows
  // Row-major, height rows of width values; the first row is the first line of the file.
  std::vector<float> coefficients;
};

}  // namespace octarc
