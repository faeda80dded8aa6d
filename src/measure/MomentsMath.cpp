#include "octarc/measure/MomentsMath.h"

#include <cmath>

#include "octarc/core/Conventions.h"

namespace octarc {

void IsoMomentAccumulator::addAll(std::span<const double> x, std::span<const double> y,
                                  std::span<const double> w) {
  double sw = sw_, swx = swx_, swy = swy_, swxx = swxx_, swyy = swyy_, swxy = swxy_;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const float dx = float(x[i] - x0_), dy = float(y[i] - y0_), wf = float(w[i]);
    const float wdx = wf * dx, wdy = wf * dy;
    sw += wf;
    swx += wdx;
    swy += wdy;
    swxx += wdx * dx;
    swyy += wdy * dy;
    swxy += wdx * dy;
  }
  sw_ = sw;
  swx_ = swx;
  swy_ = swy;
  swxx_ = swxx;
  swyy_ = swyy;
  swxy_ = swxy;
}

IsoMoments IsoMomentAccumulator::result() const {
  IsoMoments m;
  m.flux = sw_;
  if (!(sw_ > 0.0) || !std::isfinite(sw_)) return m;
  // SExtractor's one-pass form, relative to the origin: <dx^2> - <dx>^2.
  const double dxMean = swx_ / sw_, dyMean = swy_ / sw_;
  m.xMean = x0_ + dxMean;
  m.yMean = y0_ + dyMean;
  m.x2 = swxx_ / sw_ - dxMean * dxMean;
  m.y2 = swyy_ / sw_ - dyMean * dyMean;
  m.xy = swxy_ / sw_ - dxMean * dyMean;
  m.singular = applySingularFix(m.x2, m.y2, m.xy);
  m.valid = true;
  return m;
}

bool applySingularFix(double& x2, double& y2, double xy) {
  if (x2 * y2 - xy * xy < kSingularDeterminant) {
    x2 += kSingularVariance;
    y2 += kSingularVariance;
    return true;
  }
  return false;
}

EllipseShape ellipseFromMoments(double x2, double y2, double xy) {
  EllipseShape s;
  if (!std::isfinite(x2) || !std::isfinite(y2) || !std::isfinite(xy)) return s;
  const double diff = x2 - y2;
  // SExtractor's quirk: a zero difference gives exactly +45 whatever the sign of xy.
  double thetaDeg = std::fabs(diff) > 0.0 ? 0.5 * std::atan2(2.0 * xy, diff) * kDegPerRad : 45.0;
  if (thetaDeg <= -90.0) thetaDeg += 180.0;  // atan2(-0, x<0) gives -90: keep (-90, 90]
  s.thetaDeg = thetaDeg;
  const double half = 0.5 * (x2 + y2);
  const double root = std::sqrt(0.25 * diff * diff + xy * xy);
  s.a = std::sqrt(half + root);
  s.b = half > root ? std::sqrt(half - root) : 0.0;
  const double det = x2 * y2 - xy * xy;
  s.cxx = y2 / det;
  s.cyy = x2 / det;
  s.cxy = -2.0 * xy / det;
  s.elongation = s.a / s.b;
  s.ellipticity = 1.0 - s.b / s.a;
  return s;
}

CentralMoments centralMoments(std::span<const double> x, std::span<const double> y,
                              std::span<const double> w) {
  CentralMoments m;
  const std::size_t n = x.size();
  m.count = static_cast<std::int64_t>(n);
  if (n == 0 || y.size() != n || w.size() != n) {
    m.flux = 0.0;
    return m;
  }
  // Pass 1: weight sum and centroid relative to the first sample.
  const double x0 = x[0], y0 = y[0];
  double sw = 0.0, swx = 0.0, swy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sw += w[i];
    swx += w[i] * (x[i] - x0);
    swy += w[i] * (y[i] - y0);
  }
  m.flux = sw;
  if (!(sw > 0.0) || !std::isfinite(sw)) return m;
  const double cx = swx / sw, cy = swy / sw;
  // Pass 2: sums of centred offsets; no large terms cancel.
  double sxx = 0, syy = 0, sxy = 0, sxxx = 0, sxxy = 0, sxyy = 0, syyy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = (x[i] - x0) - cx, dy = (y[i] - y0) - cy;
    const double wdx = w[i] * dx, wdy = w[i] * dy;
    sxx += wdx * dx;
    syy += wdy * dy;
    sxy += wdx * dy;
    sxxx += wdx * dx * dx;
    sxxy += wdx * dx * dy;
    sxyy += wdx * dy * dy;
    syyy += wdy * dy * dy;
  }
  m.xMean = x0 + cx;
  m.yMean = y0 + cy;
  m.ixx = sxx / sw;
  m.iyy = syy / sw;
  m.ixy = sxy / sw;
  m.ixxx = sxxx / sw;
  m.ixxy = sxxy / sw;
  m.ixyy = sxyy / sw;
  m.iyyy = syyy / sw;
  m.valid = true;
  return m;
}

OctopoleStats octopoleStats(const CentralMoments& m) {
  OctopoleStats o;
  if (!m.valid) return o;
  const double trace = m.ixx + m.iyy;
  if (!(trace > 0.0) || !std::isfinite(trace)) return o;
  o.sizePix = std::sqrt(trace);
  o.e1 = (m.ixx - m.iyy) / trace;
  o.e2 = 2.0 * m.ixy / trace;
  o.e = std::hypot(o.e1, o.e2);
  double theta = 0.5 * std::atan2(2.0 * m.ixy, m.ixx - m.iyy);
  if (theta <= -0.5 * std::numbers::pi) theta += std::numbers::pi;  // keep (-pi/2, pi/2]
  o.thetaRad = theta;
  // da = c dx + s dy, db = -s dx + c dy, expanded over the moments (exact algebra).
  const double c = std::cos(theta), s = std::sin(theta);
  const double c2 = c * c, s2 = s * s;
  o.iaaa = c2 * c * m.ixxx + 3.0 * c2 * s * m.ixxy + 3.0 * c * s2 * m.ixyy + s2 * s * m.iyyy;
  o.iaab = -c2 * s * m.ixxx + (c2 * c - 2.0 * c * s2) * m.ixxy + (2.0 * c2 * s - s2 * s) * m.ixyy +
           c * s2 * m.iyyy;
  o.iabb = c * s2 * m.ixxx + (s2 * s - 2.0 * c2 * s) * m.ixxy + (c2 * c - 2.0 * c * s2) * m.ixyy +
           c2 * s * m.iyyy;
  o.ibbb = -s2 * s * m.ixxx + 3.0 * s2 * c * m.ixxy - 3.0 * s * c2 * m.ixyy + c2 * c * m.iyyy;
  const double size3 = trace * o.sizePix;
  o.arcness = std::fabs(o.iaab) / size3;
  o.antiArcness = o.iabb / size3;
  o.skewA = o.iaaa / size3;
  o.skewB = o.ibbb / size3;
  o.arcSide = o.iaab > 0.0 ? 1 : (o.iaab < 0.0 ? -1 : 0);
  o.valid = true;
  return o;
}

double isoFluxError(std::int64_t pixelCount, double sigmaAdu, double fluxAdu, double gain) {
  double var = static_cast<double>(pixelCount) * sigmaAdu * sigmaAdu;
  if (gain > 0.0 && fluxAdu > 0.0) var += fluxAdu / gain;
  return std::sqrt(var);
}

double magnitude(double fluxAdu, double magZeropoint) {
  return fluxAdu > 0.0 ? magZeropoint - 2.5 * std::log10(fluxAdu) : kMagUndefined;
}

double magnitudeError(double fluxAdu, double fluxErrAdu) {
  return fluxAdu > 0.0 ? kMagErrFactor * fluxErrAdu / fluxAdu : kMagUndefined;
}

WorldJacobian finiteDifferenceJacobian(const PixelToWorld& toWorld, double xFits, double yFits) {
  return jacobianFromSamples(toWorld(xFits, yFits), toWorld(xFits + 1.0, yFits),
                             toWorld(xFits, yFits + 1.0));
}

WorldJacobian jacobianFromSamples(const std::array<double, 2>& w0, const std::array<double, 2>& wx,
                                  const std::array<double, 2>& wy) {
  WorldJacobian j;
  auto wrap = [](double dLngDeg) {
    if (dLngDeg > 180.0) return dLngDeg - 360.0;
    if (dLngDeg < -180.0) return dLngDeg + 360.0;
    return dLngDeg;
  };
  const double cosLat = std::cos(w0[1] * kRadPerDeg);
  j.l0 = wrap(wx[0] - w0[0]) * cosLat;
  j.l1 = wrap(wy[0] - w0[0]) * cosLat;
  j.l2 = wx[1] - w0[1];
  j.l3 = wy[1] - w0[1];
  j.valid =
      std::isfinite(j.l0) && std::isfinite(j.l1) && std::isfinite(j.l2) && std::isfinite(j.l3);
  return j;
}

WorldMoments worldMoments(const WorldJacobian& j, double x2, double y2, double xy) {
  WorldMoments w;
  if (!j.valid) return w;
  // SExtractor's formulas: the cross term of X2/Y2 has no factor 2 (a documented quirk).
  w.x2 = j.l0 * j.l0 * x2 + j.l1 * j.l1 * y2 + j.l0 * j.l1 * xy;
  w.y2 = j.l2 * j.l2 * x2 + j.l3 * j.l3 * y2 + j.l2 * j.l3 * xy;
  w.xy = j.l0 * j.l2 * x2 + j.l1 * j.l3 * y2 + (j.l0 * j.l3 + j.l1 * j.l2) * xy;
  return w;
}

}  // namespace octarc
