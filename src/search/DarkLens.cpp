#include "octarc/search/DarkLens.h"

#include <numbers>

namespace octarc {

bool counterImagePlace(const CircleFit& circle, double xArc, double yArc, double xS, double yS) {
  const double ax = xArc - circle.xCentre, ay = yArc - circle.yCentre;
  const double sx = xS - circle.xCentre, sy = yS - circle.yCentre;
  const double arcDistance = std::hypot(ax, ay), distance = std::hypot(sx, sy);
  if (!(distance < circle.radius) || !(arcDistance > 0.0) || !(distance > 0.0)) return false;
  const double cosAngle = (ax * sx + ay * sy) / (arcDistance * distance);
  return cosAngle < std::cos(kCounterImageMinAngleDeg * std::numbers::pi / 180.0);
}

bool sameColour(const Colour& a, const Colour& b, const ColourMatch& match) {
  const double error = std::hypot(a.error, b.error);
  const double tolerance = std::hypot(match.sigmas * error, match.floorMag);
  return std::abs(a.value - b.value) <= tolerance;  // false for NaN
}

bool lensFreeCentre(const CircleFit& circle, const std::vector<LensCandidateGalaxy>& others) {
  for (const LensCandidateGalaxy& g : others) {
    if (std::hypot(g.x - circle.xCentre, g.y - circle.yCentre) <
        kLensFreeFraction * circle.radius) {
      return false;
    }
  }
  return true;
}

}  // namespace octarc
