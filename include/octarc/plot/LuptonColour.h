// The colour mapping of Lupton et al. (2004, PASP 116, 133) for colour composite stamps: three
// fluxes of one pixel (red, green, blue channels, on one flux scale) to an 8-bit RGB colour.
// The asinh stretch is applied to the total intensity I = (R + G + B) / 3, each channel then
// scaled by the same factor asinh(Q I / stretch) / (Q I), so that the ratios of the channels
// (the hue) are those of the fluxes; a channel above 1 scales all three down by the largest
// (the hue kept, not clipped to white); negative channels are 0.
#pragma once

#include <cstdint>

namespace octarc {

struct LuptonStretch {
  double q = 5.0;           // Q: the asinh's non-linearity
  double stretchAdu = 1.0;  // the softening: I is linear below about stretchAdu / Q
};

struct Rgb8 {
  std::uint8_t red = 0, green = 0, blue = 0;
};

// Black for a non-finite flux, I <= 0, or a stretch that is not positive.
Rgb8 luptonRgb(double redAdu, double greenAdu, double blueAdu, const LuptonStretch& stretch);

}  // namespace octarc
