#include "octarc/plot/LuptonColour.h"

#include <algorithm>
#include <cmath>

namespace octarc {

Rgb8 luptonRgb(double redAdu, double greenAdu, double blueAdu, const LuptonStretch& stretch) {
  if (!std::isfinite(redAdu) || !std::isfinite(greenAdu) || !std::isfinite(blueAdu) ||
      !(stretch.q > 0) || !(stretch.stretchAdu > 0)) {
    return {};
  }
  const double intensity = (redAdu + greenAdu + blueAdu) / 3.0;
  if (!(intensity > 0)) return {};
  const double qi = stretch.q * intensity;
  const double factor = std::asinh(qi / stretch.stretchAdu) / qi;
  double r = std::max(redAdu * factor, 0.0);
  double g = std::max(greenAdu * factor, 0.0);
  double b = std::max(blueAdu * factor, 0.0);
  const double top = std::max({r, g, b});
  if (top > 1.0) {
    r /= top;
    g /= top;
    b /= top;
  }
  const auto byte = [](double v) {
    return std::uint8_t(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
  };
  return {byte(r), byte(g), byte(b)};
}

}  // namespace octarc
