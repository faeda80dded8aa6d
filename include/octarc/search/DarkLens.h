// The paper's dark-lens criterion (METHOD.md section 4): a primary arc plus a secondary image of
// the same colour on the opposite side of the lens at smaller separation, with no visible lens.
//
// The lens position is taken to be the centre C of the arc's circle of curvature (radius R).
// A counter-image S of an arc at A lies inside that circle (|S - C| < R: the less magnified
// image is nearer the lens) and on the far side of C (the angle between A - C and S - C above
// kCounterImageMinAngleDeg). "No visible lens": no other object within kLensFreeFraction R of C.
#pragma once

#include <cmath>
#include <vector>

#include "octarc/measure/Colour.h"
#include "octarc/search/LensFinder.h"

namespace octarc {

inline constexpr double kCounterImageMinAngleDeg = 120.0;
inline constexpr double kLensFreeFraction = 0.5;

// How close two colours must be to be "the same": |c1 - c2| <= hypot(sigmas * e, floorMag),
// with e the two colours' errors in quadrature (DARK_PAIR_COLOUR).
struct ColourMatch {
  double sigmas = 2.0;
  double floorMag = 0.1;
};

// True when (xS, yS) lies where a counter-image of the arc at (xArc, yArc) would.
bool counterImagePlace(const CircleFit& circle, double xArc, double yArc, double xS, double yS);

// True when the colours agree within `match`; false when either is NaN.
bool sameColour(const Colour& a, const Colour& b, const ColourMatch& match);

// True when no point of `others` (x, y) lies within kLensFreeFraction R of the circle's centre.
bool lensFreeCentre(const CircleFit& circle, const std::vector<LensCandidateGalaxy>& others);

}  // namespace octarc
