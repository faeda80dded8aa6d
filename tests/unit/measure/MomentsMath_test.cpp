// Pure moment arithmetic against hand-computed values, SExtractor's own output on the same
// pixels (SEXTRACTOR.md §9) and the analytic cases of METHOD.md §1.
#include "octarc/measure/MomentsMath.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "ArcClosedForm.h"
#include "octarc/core/Conventions.h"

namespace octarc {
namespace {

constexpr double kPi = std::numbers::pi;

// A weighted point set, the input of the pure functions.
struct Points {
  std::vector<double> x, y, w;
  void add(double px, double py, double pw) {
    x.push_back(px);
    y.push_back(py);
    w.push_back(pw);
  }
};

IsoMoments isoOf(const Points& p) {
  double xMin = p.x[0], yMin = p.y[0];
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    xMin = std::min(xMin, p.x[i]);
    yMin = std::min(yMin, p.y[i]);
  }
  IsoMomentAccumulator acc(xMin, yMin);
  for (std::size_t i = 0; i < p.x.size(); ++i) acc.add(p.x[i], p.y[i], p.w[i]);
  return acc.result();
}

OctopoleStats octOf(const Points& p) {
  return octopoleStats(centralMoments(p.x, p.y, p.w));
}

// ---- SExtractor isophotal moments -----------------------------------------------------------
// Hand-computed values of the objects of SEXTRACTOR.md §9, whose source-extractor 2.25 run (the
// command is recorded there) printed the same digits; Plugins.EveryObjectMatchesSourceExtractor
// runs source-extractor on them again.

TEST(IsoMoments, Block3x2MatchesSExtractor) {
  Points p;  // 1-based x 10-12, y 5-6, value 10
  for (int y = 4; y <= 5; ++y)
    for (int x = 9; x <= 11; ++x) p.add(x, y, 10.0);
  const IsoMoments m = isoOf(p);
  ASSERT_TRUE(m.valid);
  EXPECT_FALSE(m.singular);
  EXPECT_DOUBLE_EQ(m.flux, 60.0);
  EXPECT_DOUBLE_EQ(toFitsPixel(m.xMean), 11.0);
  EXPECT_DOUBLE_EQ(toFitsPixel(m.yMean), 5.5);
  EXPECT_NEAR(m.x2, 2.0 / 3.0, 1e-14);
  EXPECT_NEAR(m.y2, 0.25, 1e-14);
  EXPECT_NEAR(m.xy, 0.0, 1e-14);
  const EllipseShape s = ellipseFromMoments(m.x2, m.y2, m.xy);
  // Eigenvalues 2/3 and 1/4: A = sqrt(2/3), B = 1/2; CXX = 1/X2, CYY = 1/Y2 when XY = 0.
  EXPECT_NEAR(s.a, std::sqrt(2.0 / 3.0), 1e-14);
  EXPECT_NEAR(s.b, 0.5, 1e-12);
  EXPECT_NEAR(s.thetaDeg, 0.0, 1e-12);
  EXPECT_NEAR(s.cxx, 1.5, 1e-12);
  EXPECT_NEAR(s.cyy, 4.0, 1e-12);
  EXPECT_NEAR(s.cxy, 0.0, 1e-12);
  EXPECT_NEAR(s.elongation, 2.0 * std::sqrt(2.0 / 3.0), 1e-14);
  EXPECT_NEAR(s.ellipticity, 1.0 - 0.5 / std::sqrt(2.0 / 3.0), 1e-14);
}

TEST(IsoMoments, DiagonalGetsSingularFix) {
  Points p;  // 5-pixel diagonal of 5s: one object by 8-connectivity
  for (int k = 0; k < 5; ++k) p.add(20 + k, 20 + k, 5.0);
  const IsoMoments m = isoOf(p);
  ASSERT_TRUE(m.valid);
  EXPECT_TRUE(m.singular);  // X2*Y2 - XY^2 = 0 < 0.00694
  EXPECT_NEAR(m.x2, 2.0 + 0.0833333, 1e-12);
  EXPECT_NEAR(m.y2, 2.0 + 0.0833333, 1e-12);
  EXPECT_NEAR(m.xy, 2.0, 1e-12);
  const EllipseShape s = ellipseFromMoments(m.x2, m.y2, m.xy);
  // With v = 0.0833333: X2 = Y2 = 2 + v, XY = 2, eigenvalues 4 + v and v, D = (2 + v)^2 - 4;
  // CXX = CYY = (2 + v)/D, CXY = -2 XY/D (source-extractor printed 6.1224513, -11.755107).
  const double v = kSingularVariance, d = (2.0 + v) * (2.0 + v) - 4.0;
  EXPECT_NEAR(s.b, std::sqrt(v), 1e-12);
  EXPECT_NEAR(s.a, std::sqrt(4.0 + v), 1e-12);
  EXPECT_DOUBLE_EQ(s.thetaDeg, 45.0);
  EXPECT_NEAR(s.cxx, (2.0 + v) / d, 1e-9);
  EXPECT_NEAR(s.cyy, (2.0 + v) / d, 1e-9);
  EXPECT_NEAR(s.cxy, -4.0 / d, 1e-9);
  EXPECT_NEAR(s.elongation, std::sqrt((4.0 + v) / v), 1e-9);
  EXPECT_NEAR(s.ellipticity, 1.0 - std::sqrt(v / (4.0 + v)), 1e-12);
}

// The batch form keeps its sums in registers: the same additions in the same order.
TEST(IsoMoments, AddAllEqualsAddOneByOne) {
  std::vector<double> x, y, w;
  for (int i = 0; i < 997; ++i) {
    x.push_back(1000.0 + (i * 37) % 53);
    y.push_back(2000.0 + (i * 11) % 41);
    w.push_back(std::sin(0.1 * i) * 1e3 + 1.0 / (i + 3));
  }
  IsoMomentAccumulator one(1000.0, 2000.0), all(1000.0, 2000.0);
  for (std::size_t i = 0; i < x.size(); ++i) one.add(x[i], y[i], w[i]);
  all.addAll(x, y, w);
  const IsoMoments a = one.result(), b = all.result();
  EXPECT_EQ(a.flux, b.flux);
  EXPECT_EQ(a.xMean, b.xMean);
  EXPECT_EQ(a.yMean, b.yMean);
  EXPECT_EQ(a.x2, b.x2);
  EXPECT_EQ(a.y2, b.y2);
  EXPECT_EQ(a.xy, b.xy);
}

TEST(IsoMoments, SinglePixel) {
  Points p;
  p.add(7, 3, 42.0);
  const IsoMoments m = isoOf(p);
  ASSERT_TRUE(m.valid);
  EXPECT_TRUE(m.singular);
  EXPECT_DOUBLE_EQ(m.x2, kSingularVariance);
  EXPECT_DOUBLE_EQ(m.y2, kSingularVariance);
  const EllipseShape s = ellipseFromMoments(m.x2, m.y2, m.xy);
  EXPECT_DOUBLE_EQ(s.a, std::sqrt(kSingularVariance));
  EXPECT_DOUBLE_EQ(s.b, std::sqrt(kSingularVariance));
  EXPECT_DOUBLE_EQ(s.thetaDeg, 45.0);
}

TEST(IsoMoments, AntiDiagonalGivesPlus45) {
  Points p;  // x2 == y2 with xy < 0: SExtractor still writes +45
  for (int k = 0; k < 5; ++k) p.add(20 + k, 24 - k, 5.0);
  const IsoMoments m = isoOf(p);
  EXPECT_NEAR(m.xy, -2.0, 1e-12);
  const EllipseShape s = ellipseFromMoments(m.x2, m.y2, m.xy);
  EXPECT_DOUBLE_EQ(s.thetaDeg, 45.0);
  EXPECT_GT(s.cxy, 0.0);
}

TEST(IsoMoments, VerticalLineGives90) {
  Points p;
  for (int k = 0; k < 4; ++k) p.add(5, 10 + k, 3.0);
  const IsoMoments m = isoOf(p);
  const EllipseShape s = ellipseFromMoments(m.x2, m.y2, m.xy);
  EXPECT_DOUBLE_EQ(s.thetaDeg, 90.0);
  // Negative zero in XY must not give -90 either.
  EXPECT_DOUBLE_EQ(ellipseFromMoments(0.1, 1.0, -0.0).thetaDeg, 90.0);
}

TEST(IsoMoments, ThetaAlwaysInRange) {
  for (int i = 0; i < 360; ++i) {
    const double phi = i * kPi / 180.0;
    const double x2 = 2.0 + std::cos(phi), y2 = 2.0 - std::cos(phi), xy = std::sin(phi);
    const double theta = ellipseFromMoments(x2, y2, xy).thetaDeg;
    EXPECT_GT(theta, -90.0);
    EXPECT_LE(theta, 90.0);
    if (i != 90 && i != 270) {
      EXPECT_NEAR(theta, std::remainder(i / 2.0, 180.0), 1e-9) << i;
    }
  }
}

TEST(IsoMoments, NonPositiveFluxIsInvalidNotThrown) {
  Points p;
  p.add(1, 1, 3.0);
  p.add(2, 1, -5.0);
  const IsoMoments m = isoOf(p);
  EXPECT_FALSE(m.valid);
  EXPECT_TRUE(std::isnan(m.xMean));
  EXPECT_TRUE(std::isnan(m.x2));
}

// ---- Photometry ---------------------------------------------------------------------------

TEST(Photometry, FluxErrorAndMagnitudesOfTheBlock) {
  // SEXTRACTOR.md §4: 6 pixels, sigma 1, gain 2, flux 60 -> sqrt(6 + 30) = 6.
  EXPECT_DOUBLE_EQ(isoFluxError(6, 1.0, 60.0, 2.0), 6.0);
  EXPECT_DOUBLE_EQ(isoFluxError(6, 1.0, 60.0, 0.0), std::sqrt(6.0));   // gain 0 = infinite
  EXPECT_DOUBLE_EQ(isoFluxError(6, 1.0, -60.0, 2.0), std::sqrt(6.0));  // no Poisson term for F<0
  EXPECT_NEAR(magnitude(60.0, 25.0), 20.5546, 5e-5);
  EXPECT_NEAR(magnitudeError(60.0, 6.0), 0.1086, 1e-12);
  EXPECT_EQ(magnitude(0.0, 25.0), 99.0);
  EXPECT_EQ(magnitudeError(-1.0, 6.0), 99.0);
}

// ---- Octopole statistics: METHOD.md §1 ----------------------------------------------------

// A pixelised thick arc: a Gaussian ring profile of radius R around (cx, cy), with a smooth
// taper in angle around the direction dirRad, brighter towards one end when lopsided != 0.
// Pixels on an integer grid.
Points pixelArc(double cx, double cy, double radius, double halfOpeningRad, double dirRad,
                double widthPix = 1.2, double lopsided = 0.0) {
  Points p;
  const int reach = int(radius + 4 * widthPix) + 2;
  for (int iy = int(cy) - reach; iy <= int(cy) + reach; ++iy) {
    for (int ix = int(cx) - reach; ix <= int(cx) + reach; ++ix) {
      const double dx = ix - cx, dy = iy - cy;
      const double r = std::hypot(dx, dy);
      const double ang = std::remainder(std::atan2(dy, dx) - dirRad, 2 * kPi);
      const double ringW = std::exp(-0.5 * (r - radius) * (r - radius) / (widthPix * widthPix));
      const double taper = 0.5 * (1.0 - std::tanh((std::fabs(ang) - halfOpeningRad) / 0.15));
      const double w = ringW * taper * (1.0 + lopsided * ang);
      if (w > 1e-4) p.add(ix, iy, w);
    }
  }
  return p;
}

// Direct summation in the rotated frame, independent of the closed-form rotation.
OctopoleStats directOctopoles(const Points& p) {
  const CentralMoments m = centralMoments(p.x, p.y, p.w);
  const double theta = 0.5 * std::atan2(2 * m.ixy, m.ixx - m.iyy);
  const double c = std::cos(theta), s = std::sin(theta);
  OctopoleStats o;
  double aab = 0, abb = 0, aaa = 0, bbb = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    const double dx = p.x[i] - m.xMean, dy = p.y[i] - m.yMean;
    const double da = c * dx + s * dy, db = -s * dx + c * dy;
    aab += p.w[i] * da * da * db;
    abb += p.w[i] * da * db * db;
    aaa += p.w[i] * da * da * da;
    bbb += p.w[i] * db * db * db;
  }
  o.iaab = aab / m.flux;
  o.iabb = abb / m.flux;
  o.iaaa = aaa / m.flux;
  o.ibbb = bbb / m.flux;
  return o;
}

TEST(Octopole, ClosedFormRotationMatchesDirectSums) {
  const Points p = pixelArc(30.3, 20.7, 8.0, 1.0, 0.7);
  const OctopoleStats o = octOf(p);
  const OctopoleStats d = directOctopoles(p);
  ASSERT_TRUE(o.valid);
  EXPECT_NEAR(o.iaab, d.iaab, 1e-10);
  EXPECT_NEAR(o.iabb, d.iabb, 1e-10);
  EXPECT_NEAR(o.iaaa, d.iaaa, 1e-10);
  EXPECT_NEAR(o.ibbb, d.ibbb, 1e-10);
  EXPECT_GT(std::fabs(o.iaab), 0.1);  // a real arc, not a trivially zero case
}

TEST(Octopole, HandComputedThreePoints) {
  // Points (0,0), (2,0) weight 1 and (1,1) weight 2: centroid (1, 0.5); Ixx = 0.5, Iyy = 0.25,
  // Ixy = 0, so theta = 0 (a = x, b = y). Offsets (-1,-0.5), (1,-0.5), (0,0.5).
  // I_aab = (1*(-0.5) + 1*(-0.5) + 0)/4 = -0.25; I_abb = (-0.25 + 0.25 + 0)/4 = 0;
  // I_aaa = 0; I_bbb = (-0.125 - 0.125 + 2*0.125)/4 = 0.
  Points p;
  p.add(0, 0, 1);
  p.add(2, 0, 1);
  p.add(1, 1, 2);
  const OctopoleStats o = octOf(p);
  ASSERT_TRUE(o.valid);
  EXPECT_NEAR(o.thetaRad, 0.0, 1e-15);
  EXPECT_NEAR(o.sizePix, std::sqrt(0.75), 1e-15);
  EXPECT_NEAR(o.e1, 0.25 / 0.75, 1e-15);
  EXPECT_NEAR(o.e2, 0.0, 1e-15);
  EXPECT_NEAR(o.iaab, -0.25, 1e-15);
  EXPECT_NEAR(o.iabb, 0.0, 1e-15);
  EXPECT_NEAR(o.iaaa, 0.0, 1e-15);
  EXPECT_NEAR(o.ibbb, 0.0, 1e-15);
  EXPECT_NEAR(o.arcness, 0.25 / std::pow(0.75, 1.5), 1e-14);
  EXPECT_EQ(o.arcSide, -1);  // the ends bend towards -y: centre of curvature on -b
}

TEST(Octopole, MirrorAboutMinorAxis) {
  // Arc opening downwards, centre of curvature below: symmetric under x -> -x about x = 40.
  const Points p = pixelArc(40.0, 20.0, 9.0, 0.9, kPi / 2);
  const OctopoleStats o = octOf(p);
  ASSERT_TRUE(o.valid);
  EXPECT_NEAR(o.thetaRad, 0.0, 1e-12);  // major axis along x
  EXPECT_NEAR(o.antiArcness, 0.0, 1e-12);
  EXPECT_NEAR(o.skewA, 0.0, 1e-12);
  EXPECT_GT(o.arcness, 0.05);
  EXPECT_GT(std::fabs(o.skewB), 1e-3);
}

TEST(Octopole, MirrorAboutMajorAxis) {
  // An egg elongated along x, skewed along x and wider on one side (not separable in x, y),
  // symmetric under y -> -y about y = 15.
  Points p;
  for (int y = 3; y <= 27; ++y)
    for (int x = 0; x <= 40; ++x) {
      const double dx = x - 20.0, dy = y - 15.0;
      const double sigmaY2 = 4.0 * (1.0 + 0.5 * std::tanh(dx / 6.0));
      p.add(x, y,
            std::exp(-0.5 * (dx * dx / 36.0 + dy * dy / sigmaY2)) * (1.5 + std::tanh(dx / 4.0)));
    }
  const OctopoleStats o = octOf(p);
  ASSERT_TRUE(o.valid);
  EXPECT_NEAR(o.thetaRad, 0.0, 1e-12);
  EXPECT_NEAR(o.iaab, 0.0, 1e-10);
  EXPECT_NEAR(o.skewB, 0.0, 1e-12);
  EXPECT_GT(std::fabs(o.skewA), 1e-2);
  EXPECT_GT(std::fabs(o.antiArcness), 1e-3);
}

TEST(Octopole, PointSymmetricHasNoOctopoles) {
  // An S shape: two opposite arcs, invariant under (x, y) -> (-x, -y) about (25, 25).
  Points p;
  const Points upper = pixelArc(25.0, 29.0, 6.0, 1.0, 0.0);
  for (std::size_t i = 0; i < upper.x.size(); ++i) {
    p.add(upper.x[i], upper.y[i], upper.w[i]);
    p.add(50.0 - upper.x[i], 50.0 - upper.y[i], upper.w[i]);
  }
  const OctopoleStats o = octOf(p);
  ASSERT_TRUE(o.valid);
  EXPECT_GT(o.e, 0.1);
  EXPECT_NEAR(o.iaab, 0.0, 1e-10);
  EXPECT_NEAR(o.iabb, 0.0, 1e-10);
  EXPECT_NEAR(o.iaaa, 0.0, 1e-10);
  EXPECT_NEAR(o.ibbb, 0.0, 1e-10);
}

TEST(Octopole, RotationBy90DegreesExactly) {
  const Points p = pixelArc(30.0, 30.0, 8.0, 0.8, 0.3, 1.2, 0.3);
  Points r;  // (x, y) -> (-y, x) about the origin: exact on the pixel grid
  for (std::size_t i = 0; i < p.x.size(); ++i) r.add(-p.y[i], p.x[i], p.w[i]);
  const OctopoleStats a = octOf(p), b = octOf(r);
  EXPECT_NEAR(a.sizePix, b.sizePix, 1e-12);
  EXPECT_NEAR(a.e, b.e, 1e-12);
  EXPECT_NEAR(a.arcness, b.arcness, 1e-12);
  // theta moves by 90 deg and wraps back into (-90, 90], which reverses both axes of the
  // frame: odd moments change sign together, magnitudes are unchanged.
  const double sign = (a.thetaRad + kPi / 2 > kPi / 2) ? -1.0 : 1.0;
  EXPECT_NEAR(b.antiArcness, sign * a.antiArcness, 1e-12);
  EXPECT_NEAR(b.skewA, sign * a.skewA, 1e-12);
  EXPECT_NEAR(b.skewB, sign * a.skewB, 1e-12);
  EXPECT_GT(std::fabs(a.antiArcness), 1e-3);  // a lopsided arc: every statistic non-zero
  EXPECT_GT(std::fabs(a.skewA), 1e-2);
}

TEST(Octopole, RotationByArbitraryAnglesWithinPixelisation) {
  // Same lopsided arc drawn at several orientations, centred off the pixel grid. Over every
  // whole degree the normalised statistics of this 1.2-pixel-wide ring of radius 10 move by at
  // most 6e-5 (and the size by 3e-5 relative) through pixelisation; the stated tolerance is
  // 5e-4. Odd statistics are compared in magnitude: the frame's axes flip when theta wraps.
  const double tol = 5e-4;
  const double half = 0.9;
  const OctopoleStats ref = octOf(pixelArc(50.0, 50.0, 10.0, half, 0.0, 1.2, 0.3));
  ASSERT_GT(ref.arcness, 0.1);
  ASSERT_GT(std::fabs(ref.antiArcness), 5e-3);
  ASSERT_GT(std::fabs(ref.skewA), 0.1);
  for (double deg : {13.0, 37.0, 61.0, 90.0, 122.0, 200.0, 311.0}) {
    const double dir = deg * kPi / 180.0;
    const Points p = pixelArc(50.3, 49.6, 10.0, half, dir, 1.2, 0.3);
    const OctopoleStats o = octOf(p);
    EXPECT_NEAR(o.arcness, ref.arcness, tol) << deg;
    EXPECT_NEAR(std::fabs(o.antiArcness), std::fabs(ref.antiArcness), tol) << deg;
    EXPECT_NEAR(std::fabs(o.skewA), std::fabs(ref.skewA), tol) << deg;
    EXPECT_NEAR(std::fabs(o.skewB), std::fabs(ref.skewB), tol) << deg;
    EXPECT_NEAR(o.e, ref.e, tol) << deg;
    EXPECT_NEAR(o.sizePix, ref.sizePix, tol * ref.sizePix) << deg;
    // The centre of curvature stays on the side ARC_SIDE names.
    const double bx = -std::sin(o.thetaRad), by = std::cos(o.thetaRad);
    const CentralMoments m = centralMoments(p.x, p.y, p.w);
    const double towardsCentre = (50.3 - m.xMean) * bx + (49.6 - m.yMean) * by;
    EXPECT_EQ(o.arcSide, towardsCentre > 0 ? 1 : -1) << deg;
  }
}

TEST(Octopole, MirroredArcFlipsArcSide) {
  const Points p = pixelArc(40.0, 20.0, 9.0, 0.9, kPi / 2);
  Points m;  // mirror about the major axis (y -> 40 - y)
  for (std::size_t i = 0; i < p.x.size(); ++i) m.add(p.x[i], 40.0 - p.y[i], p.w[i]);
  const OctopoleStats a = octOf(p), b = octOf(m);
  ASSERT_NE(a.arcSide, 0);
  EXPECT_EQ(b.arcSide, -a.arcSide);
  EXPECT_NEAR(b.arcness, a.arcness, 1e-12);
  // Centre of curvature is below the arc (at y = 20 < centroid): the -y side, and theta = 0
  // makes +b = +y, so I_aab < 0.
  EXPECT_EQ(a.arcSide, -1);
}

// A finely sampled thin arc against the closed form of ArcClosedForm.h. The midpoint rule with
// n = 20001 points integrates these smooth trigonometric moments to ~1e-9 (its error falls as
// 1/n^2), so the statistics agree to 1e-8.
TEST(Octopole, ThinCircularArcMatchesTheClosedForm) {
  const int n = 20001;
  const double radius = 100.0;
  for (double phiDeg : {5.0, 15.0, 30.0, 45.0, 60.0, 88.5, 90.0, 120.0, 150.0, 175.0}) {
    Points p;
    const double phi = phiDeg * kPi / 180.0;
    for (int k = 0; k < n; ++k) {
      const double t = -phi + (k + 0.5) * 2 * phi / n;
      p.add(radius * std::cos(t), radius * std::sin(t), 1.0);
    }
    const OctopoleStats o = octOf(p);
    const test::ArcMoments ref = test::uniformArc(radius, radius, phi);
    ASSERT_TRUE(o.valid) << phiDeg;
    EXPECT_NEAR(o.arcness, ref.arcness, 1e-8) << phiDeg;
    EXPECT_NEAR(o.e, ref.e, 1e-8) << phiDeg;
    EXPECT_NEAR(o.sizePix, ref.sizePix, 1e-8 * radius) << phiDeg;
    EXPECT_NEAR(o.antiArcness, 0.0, 1e-9) << phiDeg;  // symmetric about its minor axis
    EXPECT_NEAR(o.skewA, 0.0, 1e-9) << phiDeg;
    // Centre of curvature (the origin) lies on the +b side iff I_aab > 0.
    const CentralMoments m = centralMoments(p.x, p.y, p.w);
    const double towardsCentre = -m.xMean * -std::sin(o.thetaRad) + -m.yMean * std::cos(o.thetaRad);
    EXPECT_EQ(o.arcSide, towardsCentre > 0 ? 1 : -1) << phiDeg;
  }
}

TEST(Octopole, FarFromOriginKeepsThirdMoments) {
  const Points near = pixelArc(10.0, 10.0, 6.0, 0.8, 0.4);
  Points far;
  for (std::size_t i = 0; i < near.x.size(); ++i)
    far.add(near.x[i] + 9990.0, near.y[i] + 9990.0, near.w[i]);
  const CentralMoments a = centralMoments(near.x, near.y, near.w);
  const CentralMoments b = centralMoments(far.x, far.y, far.w);
  const auto rel = [](double u, double v) { return std::fabs(u - v) / std::fabs(u); };
  EXPECT_LT(rel(a.ixxx, b.ixxx), 1e-9);
  EXPECT_LT(rel(a.ixxy, b.ixxy), 1e-9);
  EXPECT_LT(rel(a.ixyy, b.ixyy), 1e-9);
  EXPECT_LT(rel(a.iyyy, b.iyyy), 1e-9);
  EXPECT_NEAR(b.xMean - a.xMean, 9990.0, 1e-9);

  // The naive raw-moment formula <x^3> - 3<x><x^2> + 2<x>^3 loses these digits far away.
  const auto naiveXxx = [](const Points& p) {
    double s = 0, sx = 0, sxx = 0, sxxx = 0;
    for (std::size_t i = 0; i < p.x.size(); ++i) {
      s += p.w[i];
      sx += p.w[i] * p.x[i];
      sxx += p.w[i] * p.x[i] * p.x[i];
      sxxx += p.w[i] * p.x[i] * p.x[i] * p.x[i];
    }
    const double m = sx / s;
    return sxxx / s - 3 * m * sxx / s + 2 * m * m * m;
  };
  EXPECT_GT(rel(a.ixxx, naiveXxx(far)), 1e-9);
}

TEST(Octopole, DegenerateObjects) {
  Points one;
  one.add(5, 5, 3.0);
  const CentralMoments m1 = centralMoments(one.x, one.y, one.w);
  EXPECT_TRUE(m1.valid);
  const OctopoleStats o1 = octopoleStats(m1);  // Ixx + Iyy == 0
  EXPECT_FALSE(o1.valid);
  EXPECT_TRUE(std::isnan(o1.arcness));
  EXPECT_EQ(o1.arcSide, 0);

  Points row;  // one row: defined, theta = 0, no minor-axis extent
  for (int x = 0; x < 5; ++x) row.add(x, 3, 1.0 + x);
  const OctopoleStats o2 = octOf(row);
  EXPECT_TRUE(o2.valid);
  EXPECT_DOUBLE_EQ(o2.e, 1.0);
  EXPECT_EQ(o2.iaab, 0.0);
  EXPECT_EQ(o2.arcSide, 0);
  EXPECT_NE(o2.iaaa, 0.0);

  Points negative;
  negative.add(1, 1, 2.0);
  negative.add(2, 2, -3.0);
  const CentralMoments m3 = centralMoments(negative.x, negative.y, negative.w);
  EXPECT_FALSE(m3.valid);
  EXPECT_FALSE(octopoleStats(m3).valid);

  const CentralMoments empty = centralMoments({}, {}, {});
  EXPECT_FALSE(empty.valid);
}

// ---- World frame --------------------------------------------------------------------------

TEST(World, JacobianOfALinearMapIsItsMatrix) {
  // lng = 359.5 + CD11 dx + CD12 dy modulo 360 (so the +1 pixel step wraps), lat = CD21 dx + CD22
  // dy, with the evaluation point at lat = 0 so cos(lat) = 1.
  const PixelToWorld linear = [](double x, double y) {
    const double dx = x - 10.0, dy = y - 20.0;
    return std::array<double, 2>{std::fmod(359.5 + 2.0 * dx + 1.0 * dy, 360.0),
                                 0.5 * dx + 3.0 * dy};
  };
  const WorldJacobian j = finiteDifferenceJacobian(linear, 10.0, 20.0);
  ASSERT_TRUE(j.valid);
  EXPECT_NEAR(j.l0, 2.0, 1e-12);
  EXPECT_NEAR(j.l1, 1.0, 1e-12);
  EXPECT_NEAR(j.l2, 0.5, 1e-12);
  EXPECT_NEAR(j.l3, 3.0, 1e-12);
}

TEST(World, JacobianScalesLongitudeByCosLatitude) {
  const PixelToWorld map = [](double x, double y) {
    return std::array<double, 2>{std::fmod(359.5 + 0.25 * x, 360.0), 60.0 + 0.001 * (y - 1.0)};
  };
  // From x = 1 to 2 the longitude goes 359.75 -> 0: wrapped to +0.25, times cos(60) = 0.5.
  const WorldJacobian j = finiteDifferenceJacobian(map, 1.0, 1.0);
  EXPECT_NEAR(j.l0, 0.125, 1e-12);
  EXPECT_NEAR(j.l1, 0.0, 1e-12);
  EXPECT_NEAR(j.l3, 0.001, 1e-12);
  // The same from the three world positions given directly.
  const WorldJacobian k = jacobianFromSamples(map(1.0, 1.0), map(2.0, 1.0), map(1.0, 2.0));
  EXPECT_EQ(k.l0, j.l0);
  EXPECT_EQ(k.l1, j.l1);
  EXPECT_EQ(k.l2, j.l2);
  EXPECT_EQ(k.l3, j.l3);
  EXPECT_TRUE(k.valid);
}

TEST(World, MomentsUseSExtractorFormulaWithoutFactorTwo) {
  WorldJacobian j;
  j.l0 = 2.0;
  j.l1 = 1.0;
  j.l2 = 0.0;
  j.l3 = 3.0;
  j.valid = true;
  // X2 = 1, Y2 = 2, XY = 0.5 by hand:
  // X2W = 4*1 + 1*2 + 2*1*0.5 = 7 (the exact J M J^T would give 8)
  // Y2W = 0 + 9*2 + 0 = 18; XYW = 0 + 1*3*2 + (2*3 + 1*0)*0.5 = 9.
  const WorldMoments w = worldMoments(j, 1.0, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(w.x2, 7.0);
  EXPECT_DOUBLE_EQ(w.y2, 18.0);
  EXPECT_DOUBLE_EQ(w.xy, 9.0);
}

TEST(World, GaussianMatchesSourceExtractorCatalog) {
  // The expected values are what source-extractor 2.25 writes for the Gaussian of
  // tests/unit/measure/Plugins_test.cpp (smallImage(): 64 x 48 float, peak 100, sigma 4 and 2
  // along axes at 30 deg, centred at 0-based (45.3, 35.7)) written with a TAN header: CRVAL
  // (150, 2), CRPIX (32, 24), CD = 1e-4 deg x rotation by 30 deg (CD1_1 = -c, CD1_2 = s,
  // CD2_1 = s, CD2_2 = c). Command (Plugins.WorldColumnsMatchSourceExtractorThroughWcs runs it
  // and compares every world column with octarc's through the real WCS):
  //   source-extractor small.fits -c /usr/share/source-extractor/default.sex
  //     -CATALOG_TYPE ASCII_HEAD -THRESH_TYPE ABSOLUTE -DETECT_THRESH 1 -ANALYSIS_THRESH 1
  //     -DETECT_MINAREA 1 -FILTER N -DEBLEND_NTHRESH 1 -DEBLEND_MINCONT 1 -CLEAN N
  //     -MASK_TYPE NONE -BACK_TYPE MANUAL -BACK_VALUE 0 -GAIN 2 -MAG_ZEROPOINT 25
  //   with X_IMAGE 46.3002, Y_IMAGE 36.6980, X2_IMAGE 1.2395482203e+01,
  //   Y2_IMAGE 6.6939450620e+00, XY_IMAGE 4.9727522818e+00 (the inputs below), and
  //   X2_WORLD 8.8168363032e-08, Y2_WORLD 1.0272591002e-07, XY_WORLD -4.9552161170e-08,
  //   A_WORLD 0.0003814853, B_WORLD 0.0002129865, THETA_WORLD -49.18.
  // Here the pure functions get a linear stand-in of that TAN WCS (good to ~1e-6 relative this
  // close to CRPIX), hence the 1e-5 tolerances.
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6), scale = 1e-4;
  const PixelToWorld linear = [&](double x, double y) {
    const double dx = x - 32.0, dy = y - 24.0;
    const double xi = scale * (-c * dx + s * dy), eta = scale * (s * dx + c * dy);
    return std::array<double, 2>{150.0 + xi / std::cos((2.0 + eta) * kPi / 180.0), 2.0 + eta};
  };
  const WorldJacobian j = finiteDifferenceJacobian(linear, 46.3002, 36.6980);
  const WorldMoments w = worldMoments(j, 1.2395482203e+01, 6.6939450620e+00, 4.9727522818e+00);
  EXPECT_NEAR(w.x2, 8.8168363032e-08, 1e-5 * 8.8e-08);
  EXPECT_NEAR(w.y2, 1.0272591002e-07, 1e-5 * 1.0e-07);
  EXPECT_NEAR(w.xy, -4.9552161170e-08, 1e-5 * 5.0e-08);
  const EllipseShape e = ellipseFromMoments(w.x2, w.y2, w.xy);
  EXPECT_NEAR(e.a, 0.0003814853, 1e-5 * 3.8e-4);
  EXPECT_NEAR(e.b, 0.0002129865, 1e-5 * 2.1e-4);
  EXPECT_NEAR(e.thetaDeg, -49.18, 0.005);
}

TEST(World, InvalidJacobianGivesNaN) {
  const PixelToWorld failing = [](double, double) { return std::array<double, 2>{kNaN, kNaN}; };
  const WorldJacobian j = finiteDifferenceJacobian(failing, 1.0, 1.0);
  EXPECT_FALSE(j.valid);
  EXPECT_TRUE(std::isnan(worldMoments(j, 1.0, 1.0, 0.0).x2));
}

// Arcness has no upper bound: the thin arc's 0.231 is the largest of uniform arcs only. Two
// faint points at (+-L, c) of weight eps each, balanced by the rest of the flux at (0, y0) below
// the centroid, give I_aab = 2 eps L^2 c, Ixx = 2 eps L^2 and Iyy = 2 eps c^2 + (1 - 2 eps) y0^2:
// for eps = 0.01, L = 10, c = 5 an arcness of 10 / 2.5102^1.5 = 2.514 (README, "ARCNESS").
TEST(Octopole, ArcnessHasNoUpperBound) {
  const double eps = 0.01, L = 10.0, c = 5.0, y0 = -2.0 * eps * c / (1.0 - 2.0 * eps);
  const std::vector<double> x = {-L, L, 0.0}, y = {c, c, y0}, w = {eps, eps, 1.0 - 2.0 * eps};
  const OctopoleStats o = octopoleStats(centralMoments(x, y, w));
  ASSERT_TRUE(o.valid);
  const double iyy = 2.0 * eps * c * c + (1.0 - 2.0 * eps) * y0 * y0;
  const double expected = 2.0 * eps * L * L * c / std::pow(2.0 * eps * L * L + iyy, 1.5);
  EXPECT_NEAR(expected, 2.514, 5e-4);
  EXPECT_NEAR(o.arcness, expected, 1e-12);
}

}  // namespace
}  // namespace octarc
