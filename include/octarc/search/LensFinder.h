// The lens of an arc candidate (METHOD.md section 4): the galaxy with the brightest peak on the
// arc's concave side within a search radius, ties going to the one nearest the arc's centre of
// curvature; and its Einstein radius, from a counter-image, the arc's curvature or the arc-lens
// distance (estimateEinsteinRadius).
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
#include <limits>
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
  // How bright its brightest peak is: the highest threshold level its object reaches, then its
  // peak pixel value (NaN when unknown). A lens is brighter at its core than an arc.
  int peakLevel = 0;
  double peakFlux = std::numeric_limits<double>::quiet_NaN();
  // The brightest peak inside the arc's own object, off its centroid: an arc blended with its
  // lens, seen from the blend. Taken however near the centroid, on the concave side when known
  // (an arc's own brightest part lies on its ridge, outside its centroid, on the convex side).
  bool inArc = false;
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

// The lens of an arc: among the galaxies within maxDistancePix of the arc centroid and at least
// kSameObjectPix from it (an inArc peak at any distance), on its concave side when arc.arcSide is
// +-1 (any side when it is 0, unknown), the one whose peak is brightest (peakLevel, then peakFlux);
// among equally bright ones, the one nearest to the centre of curvature as in findLens (nearest to
// the arc centroid when the side is unknown). einsteinRadiusPix is the arc-lens distance. nullopt
// when none qualifies: a possible dark lens. Measured on injected lenses (README, "Completeness and
// purity"), the brightest peak names the lens far more often than the nearest galaxy: ground
// arcs of theta_E < 2.5" lie close to a bright lens and are often blended with it.
std::optional<LensMatch> findBrightestLens(const ArcGeometry& arc,
                                           const std::vector<LensCandidateGalaxy>& galaxies,
                                           double maxDistancePix);

// How THETA_E was estimated (the THETA_E_METHOD column).
enum class ThetaEMethod : int {
  kNone = 0,          // no lens: NaN
  kCounterImage = 1,  // half the arc to counter-image distance through the lens
  kCurvature = 2,     // the radius of the arc's circle, centred on the lens
  kDistance = 3,      // the arc-lens distance, as the outer image of a typical double
};

// For a singular isothermal sphere the two images of a double lie on opposite sides of the lens,
// at theta_E + beta and theta_E - beta: theta_E is the mean of their distances to the lens.
inline double einsteinRadiusFromDouble(double arcDistancePix, double counterDistancePix) {
  return 0.5 * (arcDistancePix + counterDistancePix);
}

// For sources spread evenly behind the lens's caustic (beta < theta_E, no magnification bias),
// half lie within theta_E / sqrt(2) of the centre: the outer image of a double lies at
// theta_E (1 + 1/sqrt 2) in the median. A strongly magnified source (beta -> 0) lies at theta_E,
// so this is low by up to that factor, 0.59.
inline constexpr double kOuterImageDistanceRatio = 1.7071067811865475;

// A counter-image is on the opposite side: at least this angle from the arc about the lens.
inline constexpr double kDoubleMinAngleDeg = 150.0;

// The arc's circle describes the lens when its centre lies within this fraction of its radius
// from the lens and the radius is between half and kCurvatureMaxRatio times the arc-lens
// distance: the centroid of an arc of half-opening phi lies inside its ridge, at R sin(phi)/phi
// (0.64 R for a half ring), and for an SIS the ridge of an off-centre image curves with a radius
// between theta_E and its distance.
inline constexpr double kCurvatureCentreFraction = 0.3;
inline constexpr double kCurvatureMaxRatio = 1.6;

struct EinsteinRadiusEstimate {
  double thetaEPix = std::numeric_limits<double>::quiet_NaN();
  ThetaEMethod method = ThetaEMethod::kNone;
  std::optional<std::size_t> counterImage;  // index in `others` of the counter-image used
};

// theta_E of an arc at (xArc, yArc) lensed by a galaxy at (xLens, yLens), by the first that
// applies: a counter-image among `others` (at least kDoubleMinAngleDeg from the arc about the
// lens, at least kSameObjectPix from it and no farther than the arc; the most opposite one);
// the arc's circle when it describes the lens; the arc-lens distance divided by
// kOuterImageDistanceRatio. NaN and kNone when the arc lies on the lens.
EinsteinRadiusEstimate estimateEinsteinRadius(double xLens, double yLens, double xArc, double yArc,
                                              const std::optional<CircleFit>& curvature,
                                              const std::vector<LensCandidateGalaxy>& others);

}  // namespace octarc
