#include "octarc/measure/Colour.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "octarc/measure/MomentsMath.h"

namespace octarc {

BandMagnitude isoMagnitude(const BandImage& band, const std::vector<PixelRun>& footprint) {
  BandMagnitude out;
  if (band.pixels == nullptr) return out;
  const ImageF& pixels = *band.pixels;
  const double sigma2 = band.sigmaAdu * band.sigmaAdu;
  double fluxAdu = 0.0, varianceSum = 0.0, poissonVar = 0.0;
  std::int64_t used = 0;
  for (const PixelRun& run : footprint) {
    if (run.y < 0 || run.y >= pixels.height()) continue;
    for (std::int32_t x = std::max(run.x0, 0); x <= run.x1 && x < pixels.width(); ++x) {
      const double v = pixels(x, run.y);
      const double var = band.variance ? double((*band.variance)(x, run.y)) : sigma2;
      // Bad pixels (NaN, or an infinite variance from WEIGHT_THRESH) are left out of the sums.
      if (!std::isfinite(v) || !std::isfinite(var)) continue;
      ++used;
      fluxAdu += v;
      varianceSum += var;
      // With a variance map the Poisson term is weighted per pixel, as WEIGHT_GAIN Y does.
      if (band.variance && band.gain > 0.0 && v > 0.0 && sigma2 > 0.0) {
        poissonVar += v / band.gain * var / sigma2;
      }
    }
  }
  if (used == 0 || !(fluxAdu > 0.0)) return out;
  double fluxErrAdu;
  if (band.variance) {
    fluxErrAdu = std::sqrt(varianceSum + (sigma2 > 0.0      ? poissonVar
                                          : band.gain > 0.0 ? fluxAdu / band.gain
                                                            : 0.0));
  } else {
    fluxErrAdu = isoFluxError(used, band.sigmaAdu, fluxAdu, band.gain);
  }
  out.mag = magnitude(fluxAdu, band.magZeropoint);
  out.magErr = magnitudeError(fluxAdu, fluxErrAdu);
  return out;
}

Colour colourOf(const BandMagnitude& band, const BandMagnitude& reference) {
  Colour c;
  if (!std::isfinite(band.mag) || !std::isfinite(reference.mag)) return c;
  c.value = band.mag - reference.mag;
  c.error = std::hypot(band.magErr, reference.magErr);
  return c;
}

bool isBandName(const std::string& name) {
  return !name.empty() && name.size() <= 16 &&
         std::all_of(name.begin(), name.end(),
                     [](unsigned char ch) { return std::isalnum(ch) || ch == '_'; });
}

}  // namespace octarc
