// Pure moment arithmetic: no images, no columns. Plugins adapt these functions to catalog
// columns; tests call them directly.
//
// Positions are 0-based pixel indices (core/Conventions.h) unless a name says Fits. Every sum is
// accumulated in double relative to a local origin near the object, so an object far from the
// image origin gets the same moments as the same object near it.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>

#include "octarc/core/Conventions.h"

namespace octarc {

// ---------------------------------------------------------------------------------------------
// SExtractor isophotal second moments (SEXTRACTOR.md §3, one-pass sums as SExtractor does them).

// Second moments of a weighted pixel set, SExtractor style.
struct IsoMoments {
  double flux = kNaN;   // sum of weights
  double xMean = kNaN;  // weighted centroid, 0-based
  double yMean = kNaN;
  double x2 = kNaN;  // X2, Y2, XY in pixel^2, after the singular fix
  double y2 = kNaN;
  double xy = kNaN;
  bool singular = false;  // the singular fix was applied
  bool valid = false;     // false when the weight sum is <= 0 (everything NaN)
};

// One-pass accumulator of SExtractor's isophotal moments. The origin must be the object's
// (xmin, ymin) to reproduce SExtractor's rounding; any point near the object keeps the precision.
// Sums are double, but each product weight * offset is formed in single precision as SExtractor
// forms it (float pixel times integer offset): with it, X2/Y2/XY agree with source-extractor
// 2.25 to all printed digits on float images, where exact double products differ by ~1e-7.
class IsoMomentAccumulator {
 public:
  IsoMomentAccumulator(double xOrigin, double yOrigin) : x0_(xOrigin), y0_(yOrigin) {}
  void add(double x, double y, double weight) {
    const float dx = float(x - x0_), dy = float(y - y0_), w = float(weight);
    sw_ += w;
    swx_ += w * dx;
    swy_ += w * dy;
    swxx_ += w * dx * dx;
    swyy_ += w * dy * dy;
    swxy_ += w * dx * dy;
  }
  // add() for every sample in order (the same sums, kept in registers).
  void addAll(std::span<const double> x, std::span<const double> y, std::span<const double> w);
  // X2 = sum w dx^2 / F - <dx>^2 etc., then the singular fix of core/Conventions.h.
  IsoMoments result() const;

 private:
  double x0_, y0_;
  double sw_ = 0, swx_ = 0, swy_ = 0, swxx_ = 0, swyy_ = 0, swxy_ = 0;
};

// SExtractor's guard: if x2*y2 - xy^2 < kSingularDeterminant, add kSingularVariance to x2 and
// y2. Returns true if it did.
bool applySingularFix(double& x2, double& y2, double xy);

// Ellipse parameters SExtractor derives from second moments.
struct EllipseShape {
  double a = kNaN;         // A: sqrt of the larger eigenvalue
  double b = kNaN;         // B: sqrt of the smaller eigenvalue
  double thetaDeg = kNaN;  // 0.5 atan2(2xy, x2 - y2) in (-90, 90]; exactly +45 when x2 == y2
  double cxx = kNaN;       // CXX = y2/D, CYY = x2/D, CXY = -2xy/D with D = x2 y2 - xy^2
  double cyy = kNaN;
  double cxy = kNaN;
  double elongation = kNaN;   // A/B
  double ellipticity = kNaN;  // 1 - B/A
};

// Eigen decomposition of (x2, y2, xy) with SExtractor's THETA quirk. No singular fix here: apply
// it first where SExtractor does. Degenerate inputs give NaN (or inf for A/B with B == 0), never
// a throw.
EllipseShape ellipseFromMoments(double x2, double y2, double xy);

// ---------------------------------------------------------------------------------------------
// Central moments and the octopole statistics of METHOD.md §1 (unweighted by any profile).

// Weighted central moments to third order, each divided by the weight sum.
struct CentralMoments {
  std::int64_t count = 0;  // number of samples used
  double flux = kNaN;      // sum of weights
  double xMean = kNaN;     // 0-based centroid
  double yMean = kNaN;
  double ixx = kNaN, iyy = kNaN, ixy = kNaN;                  // second order
  double ixxx = kNaN, ixxy = kNaN, ixyy = kNaN, iyyy = kNaN;  // third order
  bool valid = false;  // false when flux <= 0 (or not finite): everything NaN
};

// Two-pass central moments: the centroid first (relative to the first sample), then sums of the
// centred offsets. x, y, w have equal length.
CentralMoments centralMoments(std::span<const double> x, std::span<const double> y,
                              std::span<const double> w);

// METHOD.md §1 statistics of one object.
struct OctopoleStats {
  double sizePix = kNaN;   // s = sqrt(Ixx + Iyy)
  double e1 = kNaN;        // (Ixx - Iyy)/(Ixx + Iyy)
  double e2 = kNaN;        // 2 Ixy/(Ixx + Iyy)
  double e = kNaN;         // sqrt(e1^2 + e2^2)
  double thetaRad = kNaN;  // 0.5 atan2(2Ixy, Ixx - Iyy) in (-pi/2, pi/2]
  double iaab = kNaN;      // octopoles in the major/minor-axis frame, pixel^3
  double iabb = kNaN;
  double iaaa = kNaN;
  double ibbb = kNaN;
  double arcness = kNaN;      // |I_aab|/s^3
  double antiArcness = kNaN;  // I_abb/s^3
  double skewA = kNaN;        // I_aaa/s^3
  double skewB = kNaN;        // I_bbb/s^3
  int arcSide = 0;            // sign(I_aab): +1/-1; 0 if I_aab is zero or undefined
  bool valid = false;         // false when the moments are invalid or Ixx + Iyy == 0
};

// Rotates the third moments into the frame of the major axis and normalises them.
OctopoleStats octopoleStats(const CentralMoments& m);

// ---------------------------------------------------------------------------------------------
// Photometry (SEXTRACTOR.md §3-4).

// FLUXERR_ISO without a variance map: sqrt(n sigma^2 + F/gain), the Poisson term only when
// gain > 0 and F > 0.
double isoFluxError(std::int64_t pixelCount, double sigmaAdu, double fluxAdu, double gain);
// MAG = zp - 2.5 log10(F), kMagUndefined when F <= 0.
double magnitude(double fluxAdu, double magZeropoint);
// MAGERR = 1.086 dF/F, kMagUndefined when F <= 0.
double magnitudeError(double fluxAdu, double fluxErrAdu);

// ---------------------------------------------------------------------------------------------
// World-frame shapes (SEXTRACTOR.md §3, astrom.c).

// (longitude, latitude) in degrees of a 1-based FITS pixel position; NaN on failure.
using PixelToWorld = std::function<std::array<double, 2>(double xFits, double yFits)>;

// Local Jacobian by forward difference of +1 pixel along each axis, as SExtractor takes it:
// l0 = dlng/dx, l1 = dlng/dy, l2 = dlat/dx, l3 = dlat/dy in degrees per pixel, the longitude
// differences wrapped to [-180, 180] and multiplied by cos(latitude at the position).
struct WorldJacobian {
  double l0 = kNaN, l1 = kNaN, l2 = kNaN, l3 = kNaN;
  bool valid = false;
};
WorldJacobian finiteDifferenceJacobian(const PixelToWorld& toWorld, double xFits, double yFits);
// The same from the world positions of (x, y), (x + 1, y) and (x, y + 1).
WorldJacobian jacobianFromSamples(const std::array<double, 2>& atPixel,
                                  const std::array<double, 2>& stepX,
                                  const std::array<double, 2>& stepY);

// Second moments in the world frame, deg^2, with SExtractor's formulas, including the missing
// factor 2 of the cross term in X2/Y2_WORLD (X2W = l0^2 X2 + l1^2 Y2 + l0 l1 XY).
struct WorldMoments {
  double x2 = kNaN, y2 = kNaN, xy = kNaN;
};
WorldMoments worldMoments(const WorldJacobian& j, double x2, double y2, double xy);

}  // namespace octarc
