// The octopole statistics of a uniform circular arc in closed form, the reference for the
// arcness of thin arcs (METHOD.md section 1) and of rasterised ones.
//
// The arc: every point at radius r in [r1, r2] from its centre of curvature and at angle t in
// [-phi, phi] from the +x axis, with uniform surface brightness (weight r dr dt); r1 = r2 = R is
// the thin arc. In x = r cos t, y = r sin t every moment factorises into a radial and an angular
// mean, <x^p y^q> = M_(p+q) <cos^p t sin^q t>, with
//   M_k = <r^k> = 2 (r2^(k+2) - r1^(k+2)) / ((k+2) (r2^2 - r1^2))   (R^k for the thin arc),
//   <cos t> = sin(phi)/phi,             <sin^2 t> = 1/2 - sin(2 phi)/(4 phi),
//   <cos^2 t> = 1/2 + sin(2 phi)/(4 phi), <sin^2 t cos t> = sin^3(phi)/(3 phi),
// the odd powers of sin t averaging to 0. So the centroid is (M1 sin(phi)/phi, 0), Ixy = 0,
//   Ixx = M2 <cos^2 t> - xbar^2,   Iyy = M2 <sin^2 t>,
// and the arc is symmetric about the x axis, so of its third moments only those with an even
// power of y survive. When y is the major axis (a = y, b = x: every thin arc with 0 < phi < pi,
// since there Iyy - Ixx = R^2 (sin phi/phi)(sin phi/phi - cos phi) > 0),
//   |I_aab| = |I_xyy| = |M3 <sin^2 t cos t> - xbar M2 <sin^2 t>|;
// when x is the major axis (a short, thick arc), I_aab = I_xxy = 0. Then
// arcness = |I_aab| / (Ixx + Iyy)^(3/2) and e = |Iyy - Ixx| / (Ixx + Iyy). For the thin arc:
//   arcness = |sin^3(phi)/(3 phi) - (sin(phi)/phi) (1/2 - sin(2 phi)/(4 phi))|
//             / (1 - sin^2(phi)/phi^2)^(3/2).
#pragma once

#include <cmath>

namespace octarc::test {

struct ArcMoments {
  double arcness = 0.0;  // |I_aab| / s^3
  double e = 0.0;        // (a^2 - b^2) / (a^2 + b^2)
  double sizePix = 0.0;  // s = sqrt(Ixx + Iyy)
  double xMean = 0.0;    // centroid distance from the centre of curvature, along the mid-line
};

inline ArcMoments uniformArc(double r1, double r2, double phi) {
  const auto radial = [&](int k) {
    if (r2 - r1 < 1e-12 * r2) return std::pow(r2, k);
    return 2.0 * (std::pow(r2, k + 2) - std::pow(r1, k + 2)) / ((k + 2) * (r2 * r2 - r1 * r1));
  };
  const double sinc = std::sin(phi) / phi;
  const double sin2 = 0.5 - std::sin(2 * phi) / (4 * phi);
  const double cos2 = 0.5 + std::sin(2 * phi) / (4 * phi);
  const double sin2cos = std::pow(std::sin(phi), 3) / (3 * phi);
  ArcMoments m;
  m.xMean = radial(1) * sinc;
  const double ixx = radial(2) * cos2 - m.xMean * m.xMean;
  const double iyy = radial(2) * sin2;
  const double ixyy = radial(3) * sin2cos - m.xMean * iyy;  // <x y^2> - xbar <y^2>
  const double trace = ixx + iyy;
  m.sizePix = std::sqrt(trace);
  m.e = std::fabs(iyy - ixx) / trace;
  m.arcness = iyy > ixx ? std::fabs(ixyy) / (trace * m.sizePix) : 0.0;
  return m;
}

}  // namespace octarc::test
