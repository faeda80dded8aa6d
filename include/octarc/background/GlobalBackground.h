// One background level and one noise sigma for a whole image (BACK_TYPE GLOBAL, and the
// paper's "global RMS" of the background pixels, METHOD.md §2).
//
// Iterative kappa-sigma clipping: start from every valid pixel (finite and above SExtractor's
// blank value -1e30), then keep the pixels within median +- clipSigma * sigma of the current set
// and repeat until the set no longer changes or maxIterations clipping steps have run.
//   sigmaAdu  = standard deviation of the final set (population form, divided by N);
//   levelAdu  = SExtractor's mode estimate from the same set: 2.5 median - 1.5 mean when
//               |mean - median| < 0.3 sigma, else the median (crowded fields skew the mean).
// A constant image (sigma 0) gets sigmaAdu = 1 and a warning, as SExtractor does.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "octarc/core/Image.h"

namespace octarc {

struct GlobalBackground {
  double levelAdu = 0.0;        // mode estimate (see above)
  double sigmaAdu = 1.0;        // clipped standard deviation (1 for constant data)
  double meanAdu = 0.0;         // mean of the clipped pixels
  double medianAdu = 0.0;       // median of the clipped pixels (exact, an element of the image)
  std::int64_t pixelCount = 0;  // pixels kept by the clipping
  int iterations = 0;           // clipping steps run
  bool converged = false;       // false if maxIterations stopped it
  std::string warning;          // empty, or why a fallback value was used
};

// Throws ConfigError for clipSigma <= 0 or maxIterations < 0, IoError ("<imageName>: no valid
// pixels ...") when no pixel is usable. threadCount 0 = all hardware threads; the result never
// depends on it.
GlobalBackground estimateGlobalBackground(const ImageF& image, double clipSigma = 3.0,
                                          int maxIterations = 100,
                                          std::string_view imageName = "image",
                                          int threadCount = 0);

}  // namespace octarc
