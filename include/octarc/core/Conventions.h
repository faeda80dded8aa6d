// Every coordinate, angle and shape convention of octarc, written once.
//
// Pixels
//   In memory, pixel (x, y) has 0-based indices: x along NAXIS1 (columns), y along NAXIS2 (rows).
//   In catalogs, ASSOC lists, region files and WCS calls, positions are 1-based FITS pixel
//   coordinates, as in SExtractor: the centre of the pixel with 0-based index i is at i + 1.
//   Convert only with toFitsPixel() / fromFitsPixel().
//
// Angles
//   THETA_IMAGE and the octarc position angle are measured counter-clockwise from +x (with +y
//   up, as an image is displayed), in degrees in catalogs (names end in Deg) and radians in
//   code (names end in Rad). SExtractor range (-90, 90]; exactly +45 when X2 == Y2.
//
// Ellipticity
//   ELLIPTICITY (SExtractor) = 1 - B/A.
//   E_IMAGE (octarc, METHOD.md) = the distortion (a^2 - b^2)/(a^2 + b^2) = sqrt(e1^2 + e2^2),
//   e1 = (Ixx - Iyy)/(Ixx + Iyy), e2 = 2 Ixy/(Ixx + Iyy), from unweighted (no singular fix)
//   central second moments of the measurement image.
//
// Octopole frame
//   theta = 0.5 atan2(2 Ixy, Ixx - Iyy); da = cos(theta) dx + sin(theta) dy (major axis),
//   db = -sin(theta) dx + cos(theta) dy (minor axis). ARC_SIDE = sign(I_aab): the centre of
//   curvature lies on the +b side of the centroid when I_aab > 0.
//
// Occupation grid (selection/)
//   Bins are half-open, [lo + k w, lo + (k + 1) w); the S/N axis is log10(SNR_ISO); bins are
//   ordered by probability, ties by packed index (axis 0 fastest), lowest first. Written out in
//   selection/GridBinning.h and selection/OccupationGrid.h.
//
// Missing values
//   A quantity that cannot be measured for an object is NaN (kNaN), with a flag saying why.
#pragma once

#include <cstdint>
#include <limits>
#include <numbers>

namespace octarc {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 1-based FITS pixel coordinate of the centre of the pixel with 0-based index i.
constexpr double toFitsPixel(double zeroBasedIndex) {
  return zeroBasedIndex + 1.0;
}
// 0-based index coordinate of a 1-based FITS pixel coordinate.
constexpr double fromFitsPixel(double fitsPixel) {
  return fitsPixel - 1.0;
}

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// FWHM of a Gaussian per unit sigma, 2 sqrt(2 ln 2) (seeing, PSF kernels, fitted widths).
constexpr double kGaussianFwhmPerSigma = 2.3548200450309493;

// SExtractor's guard for singular second moments (analyse.c, preanalyse): when
// X2*Y2 - XY^2 < kSingularDeterminant, add kSingularVariance (about 1/12, the variance of a
// uniform pixel) to X2 and Y2. The literals are SExtractor's, kept bit for bit.
constexpr double kSingularDeterminant = 0.00694;
constexpr double kSingularVariance = 0.0833333;

// SExtractor's magnitude error constant 2.5/ln(10), rounded as SExtractor rounds it.
constexpr double kMagErrFactor = 1.086;
// Value SExtractor writes for an undefined magnitude.
constexpr double kMagUndefined = 99.0;

}  // namespace octarc
