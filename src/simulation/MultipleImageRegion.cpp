#include "octarc/simulation/MultipleImageRegion.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/simulation/LensSystem.h"

namespace octarc::simulation {

namespace {

// Even-odd rule; the cut is convex and the caustic a simple (astroid-like) curve, so the rule
// gives their insides.
bool insidePolygon(const std::vector<Vec2>& polygon, const Vec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a[1] > p[1]) != (b[1] > p[1]) &&
        p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0])
      inside = !inside;
  }
  return inside;
}

}  // namespace

MultipleImageRegion::MultipleImageRegion(const EllipticalPotentialParams& params, int vertices) {
  if (vertices < 16)
    throw ConfigError("multiple-image region: need at least 16 vertices, got " +
                      std::to_string(vertices));
  EllipticalPotentialParams coreless = params;
  coreless.coreArcsec = 0.0;
  const EllipticalPotentialLens lens(coreless);  // validates b and eps
  const double b = params.einsteinRadiusArcsec;
  const double a = 1.0 - params.ellipticity;  // M = diag(a, c) in the lens frame
  const double c = 1.0 + params.ellipticity;
  const double cosPa = std::cos(params.positionAngleRad);
  const double sinPa = std::sin(params.positionAngleRad);
  cut_.resize(std::size_t(vertices));
  caustic_.resize(std::size_t(vertices));
  for (int k = 0; k < vertices; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / vertices;  // lens-frame direction
    const double ux = std::cos(phi), uy = std::sin(phi);
    const double d2 = a * ux * ux + c * uy * uy;  // u^T M u
    const double d = std::sqrt(d2);
    // alpha(u) = b M u / d; trace of the Hessian at r = 1: (b / d) (tr M - u^T M^2 u / d^2).
    const double alphaX = b * a * ux / d, alphaY = b * c * uy / d;
    const double rT = b / d * (a + c - (a * a * ux * ux + c * c * uy * uy) / d2);
    const auto toSky = [&](double x, double y) {
      return Vec2{cosPa * x - sinPa * y, sinPa * x + cosPa * y};
    };
    cut_[std::size_t(k)] = toSky(-alphaX, -alphaY);
    caustic_[std::size_t(k)] = toSky(rT * ux - alphaX, rT * uy - alphaY);
  }
  for (const auto* curve : {&cut_, &caustic_})
    for (const Vec2& p : *curve)
      boundingRadiusArcsec_ = std::max(boundingRadiusArcsec_, std::hypot(p[0], p[1]));
  // Chords of the polygons lie inside the convex cut; a hair of margin keeps the disc around the
  // curves as well.
  boundingRadiusArcsec_ *= 1.0 + 1e-9;
}

bool MultipleImageRegion::contains(const Vec2& beta) const {
  return insidePolygon(cut_, beta) || insidePolygon(caustic_, beta);
}

Vec2 MultipleImageRegion::drawUniform(std::mt19937_64& rng) const {
  for (;;) {
    const Vec2 p = drawUniformInDisc(boundingRadiusArcsec_, rng);
    if (contains(p)) return p;
  }
}

}  // namespace octarc::simulation
