// The lens of an arc candidate (METHOD.md section 4): the galaxy on the arc's concave side,
// nearest to the arc's centre of curvature, within a search radius; the Einstein radius
// estimated as the arc-lens distance (the arc taken to trace the critical curve).
//
// The centre of curvature comes from a circle fitted to the arc's pixels, weighted by flux:
// Kasa's linear least squares for x^2 + y^2 + D x + E y + F = 0 (about the flux centroid, in
// double) as the start of a Gauss-Newton fit of the geometric distances |p - c| - R.
//
// The concave side is the +b side of the octopole frame when ARC_SIDE = +1
// (core/Conventions.h): a galaxy is on it when its offset from the arc centroid has a positive
// component along ARC_SIDE * (-sin THETA, cos THETA).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace octarc {

struct CircleFit {
  double xCentre = 0.0;  // in the coordinates of the points
  double yCentre = 0.0;
  double radius = 0.0;
};

// The flux-weighted circle through points (x, y) with weights w > 0 (non-positive and non-finite
// weights are left out). nullopt for inputs of different lengths, fewer than three usable
// points, a geometric fit that does not converge, or points on a line (the
// fitted radius would be unbounded).
std::optional<CircleFit> fitCircle(const std::vector<double>& x, const std::vector<double>& y,
                                   const std::vector<double>& weight);

// A galaxy that may be a lens: its position (pixels, any origin shared with the arc) and id.
struct LensCandidateGalaxy {
  double x = 0.0;
  double y = 0.0;
  std::size_t row = 0;  // the caller's row of the galaxy
};

struct ArcGeometry {
  double xCentroid = 0.0;
  double yCentroid = 0.0;
  double thetaRad = 0.0;               // major-axis angle, counter-clockwise from +x
  int arcSide = 0;                     // ARC_SIDE: +1, -1, or 0 when unknown
  std::optional<CircleFit> curvature;  // the fitted circle, if any
};

// A galaxy closer than this to the arc's centroid is the arc itself (its row at another level).
inline constexpr double kSameObjectPix = 0.5;

struct LensMatch {
  std::size_t row = 0;             // the chosen galaxy's row
  double einsteinRadiusPix = 0.0;  // arc centroid to lens distance
};

// The lens among `galaxies`: those on the concave side within maxDistancePix of the arc
// centroid, the one nearest to the centre of curvature (nearest to the arc centroid when no
// circle was fitted, or its centre is on the convex side or beyond maxDistancePix). The arc
// centroid lies inside the ridge by about sin(phi)/phi for a half-opening phi, so theta_E is
// low by that factor (6% at +-35 degrees). nullopt when none qualifies, or the side is unknown: a
// possible dark lens. Galaxies at the arc centroid itself (the arc's own row at another level) are
// skipped.
std::optional<LensMatch> findLens(const ArcGeometry& arc,
                                  const std::vector<LensCandidateGalaxy>& galaxies,
                                  double maxDistancePix);

}  // namespace octarc
