// Detection filters of the tests.
#pragma once

#include "octarc/core/ConvKernel.h"

namespace octarc::test {

// SExtractor's default.conv (1 2 1 / 2 4 2 / 1 2 1, NORM): the pyramid over 16.
inline ConvKernel defaultConvKernel() {
  ConvKernel k{3, 3, {1, 2, 1, 2, 4, 2, 1, 2, 1}};
  for (float& c : k.coefficients) c /= 16.0f;
  return k;
}

}  // namespace octarc::test
