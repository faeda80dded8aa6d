#include "octarc/search/LensFinder.h"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <utility>

namespace octarc {

std::optional<CircleFit> fitCircle(const std::vector<double>& x, const std::vector<double>& y,
                                   const std::vector<double>& weight) {
  if (y.size() != x.size() || weight.size() != x.size()) return std::nullopt;
  // Local origin at the weighted centroid: the squares below stay small.
  double sumW = 0.0;
  double sumX = 0.0;
  double sumY = 0.0;
  std::size_t used = 0;
  const auto usable = [&](std::size_t i) { return std::isfinite(weight[i]) && weight[i] > 0.0; };
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!usable(i)) continue;
    sumW += weight[i];
    sumX += weight[i] * x[i];
    sumY += weight[i] * y[i];
    ++used;
  }
  if (used < 3) return std::nullopt;
  const double x0 = sumX / sumW;
  const double y0 = sumY / sumW;
  // Normal equations of min sum w (u^2 + v^2 + D u + E v + F)^2 over (D, E, F).
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  double scale2 = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!usable(i)) continue;
    const double u = x[i] - x0;
    const double v = y[i] - y0;
    const Eigen::Vector3d row(u, v, 1.0);
    normal += weight[i] * row * row.transpose();
    rhs -= weight[i] * (u * u + v * v) * row;
    scale2 += weight[i] * (u * u + v * v);
  }
  scale2 /= sumW;
  Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
  // Collinear points make the system singular (relative to the spread of the points).
  lu.setThreshold(1e-12);
  if (lu.rank() < 3 || scale2 <= 0.0) return std::nullopt;
  const Eigen::Vector3d def = lu.solve(rhs);
  Eigen::Vector3d circle(-0.5 * def[0], -0.5 * def[1], 0.0);  // centre (local), radius
  const double r2 = circle[0] * circle[0] + circle[1] * circle[1] - def[2];
  if (!(r2 > 0.0) || !std::isfinite(r2)) return std::nullopt;
  circle[2] = std::sqrt(r2);
  // The algebraic fit shrinks the circle of a thick, short arc (its outer pixels weigh more):
  // Gauss-Newton on the geometric distances |p - c| - R from there removes that bias.
  bool converged = false;
  for (int iteration = 0; iteration < 50 && !converged; ++iteration) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (!usable(i)) continue;
      const double du = x[i] - x0 - circle[0];
      const double dv = y[i] - y0 - circle[1];
      const double d = std::hypot(du, dv);
      if (d == 0.0) continue;
      const Eigen::Vector3d j(-du / d, -dv / d, -1.0);
      jtj += weight[i] * j * j.transpose();
      jtr += weight[i] * (d - circle[2]) * j;
    }
    const Eigen::Vector3d step = jtj.ldlt().solve(-jtr);
    if (!step.allFinite()) return std::nullopt;
    circle += step;
    converged = step.norm() < 1e-10 * (1.0 + std::fabs(circle[2]));
  }
  if (!converged) return std::nullopt;
  // A radius many times the object's size is a straight object: no usable centre.
  if (!(circle[2] > 0.0) || circle[2] * circle[2] > 1e8 * scale2) return std::nullopt;
  return CircleFit{circle[0] + x0, circle[1] + y0, circle[2]};
}

namespace {

// Where findLens measures a galaxy's nearness from: the fitted centre, unless it lies on the
// convex side or beyond the search radius (a nearly straight arc): then the arc centroid.
std::pair<double, double> curvatureTarget(const ArcGeometry& arc, double nx, double ny,
                                          double maxDistancePix) {
  if (arc.curvature) {
    const double cx = arc.curvature->xCentre - arc.xCentroid;
    const double cy = arc.curvature->yCentre - arc.yCentroid;
    if (cx * nx + cy * ny > 0.0 && std::hypot(cx, cy) <= maxDistancePix) {
      return {arc.curvature->xCentre, arc.curvature->yCentre};
    }
  }
  return {arc.xCentroid, arc.yCentroid};
}

// True when a's peak is brighter than b's: the higher level, then the brighter pixel (a known
// value beats NaN).
bool brighterPeak(const LensCandidateGalaxy& a, const LensCandidateGalaxy& b) {
  if (a.peakLevel != b.peakLevel) return a.peakLevel > b.peakLevel;
  if (std::isnan(b.peakFlux)) return !std::isnan(a.peakFlux);
  return a.peakFlux > b.peakFlux;
}

bool samePeak(const LensCandidateGalaxy& a, const LensCandidateGalaxy& b) {
  return !brighterPeak(a, b) && !brighterPeak(b, a);
}

}  // namespace

std::optional<LensMatch> findLens(const ArcGeometry& arc,
                                  const std::vector<LensCandidateGalaxy>& galaxies,
                                  double maxDistancePix) {
  if (arc.arcSide == 0) return std::nullopt;
  // The unit vector from the arc centroid towards its concave side.
  const double nx = -std::sin(arc.thetaRad) * arc.arcSide;
  const double ny = std::cos(arc.thetaRad) * arc.arcSide;
  const auto [xTarget, yTarget] = curvatureTarget(arc, nx, ny, maxDistancePix);
  std::optional<LensMatch> best;
  double bestTargetDistance = 0.0;
  for (const LensCandidateGalaxy& g : galaxies) {
    const double dx = g.x - arc.xCentroid;
    const double dy = g.y - arc.yCentroid;
    const double distance = std::hypot(dx, dy);
    if (!(distance <= maxDistancePix) || distance < kSameObjectPix) continue;
    if (dx * nx + dy * ny <= 0.0) continue;  // convex side
    const double targetDistance = std::hypot(g.x - xTarget, g.y - yTarget);
    if (!best || targetDistance < bestTargetDistance) {
      best = LensMatch{g.row, distance};
      bestTargetDistance = targetDistance;
    }
  }
  return best;
}

std::optional<LensMatch> findBrightestLens(const ArcGeometry& arc,
                                           const std::vector<LensCandidateGalaxy>& galaxies,
                                           double maxDistancePix) {
  const double nx = -std::sin(arc.thetaRad) * arc.arcSide;
  const double ny = std::cos(arc.thetaRad) * arc.arcSide;
  const auto [xTarget, yTarget] = arc.arcSide != 0 ? curvatureTarget(arc, nx, ny, maxDistancePix)
                                                   : std::pair{arc.xCentroid, arc.yCentroid};
  const LensCandidateGalaxy* best = nullptr;
  double bestTargetDistance = 0.0;
  for (const LensCandidateGalaxy& g : galaxies) {
    const double dx = g.x - arc.xCentroid;
    const double dy = g.y - arc.yCentroid;
    const double distance = std::hypot(dx, dy);
    if (!g.inArc && (!(distance <= maxDistancePix) || distance < kSameObjectPix)) continue;
    if (arc.arcSide != 0 && dx * nx + dy * ny <= 0.0) continue;  // convex side
    const double targetDistance = std::hypot(g.x - xTarget, g.y - yTarget);
    if (!best || brighterPeak(g, *best) ||
        (samePeak(g, *best) && targetDistance < bestTargetDistance)) {
      best = &g;
      bestTargetDistance = targetDistance;
    }
  }
  if (best == nullptr) return std::nullopt;
  return LensMatch{best->row, std::hypot(best->x - arc.xCentroid, best->y - arc.yCentroid)};
}

EinsteinRadiusEstimate estimateEinsteinRadius(double xLens, double yLens, double xArc, double yArc,
                                              const std::optional<CircleFit>& curvature,
                                              const std::vector<LensCandidateGalaxy>& others) {
  EinsteinRadiusEstimate out;
  const double ax = xArc - xLens;
  const double ay = yArc - yLens;
  const double distance = std::hypot(ax, ay);
  if (!(distance >= kSameObjectPix)) return out;
  const double maxCos = std::cos(kDoubleMinAngleDeg * std::numbers::pi / 180.0);
  double bestCos = 0.0;
  for (std::size_t i = 0; i < others.size(); ++i) {
    const double sx = others[i].x - xLens;
    const double sy = others[i].y - yLens;
    const double counterDistance = std::hypot(sx, sy);
    if (!(counterDistance >= kSameObjectPix && counterDistance <= distance)) continue;
    const double cosAngle = (ax * sx + ay * sy) / (distance * counterDistance);
    if (cosAngle > maxCos || (out.counterImage && cosAngle >= bestCos)) continue;
    out.counterImage = i;
    out.thetaEPix = einsteinRadiusFromDouble(distance, counterDistance);
    out.method = ThetaEMethod::kCounterImage;
    bestCos = cosAngle;
  }
  if (out.counterImage) return out;
  if (curvature) {
    const double offCentre = std::hypot(curvature->xCentre - xLens, curvature->yCentre - yLens);
    if (offCentre <= kCurvatureCentreFraction * curvature->radius &&
        curvature->radius >= 0.5 * distance && curvature->radius <= kCurvatureMaxRatio * distance) {
      out.thetaEPix = curvature->radius;
      out.method = ThetaEMethod::kCurvature;
      return out;
    }
  }
  out.thetaEPix = distance / kOuterImageDistanceRatio;
  out.method = ThetaEMethod::kDistance;
  return out;
}

}  // namespace octarc
