#include "octarc/simulation/LensModel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "LensTestSupport.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/Cosmology.h"

namespace octarc::simulation {
namespace {

TEST(EllipticalPotentialLens, ImagesOfACentralSourceAreAnalytic) {
  const double b = 1.3;
  const double eps = 0.15;
  const EllipticalPotentialLens lens({b, eps, 0.0, 0.0});
  const double onMajor = b * std::sqrt(1.0 - eps);
  const double onMinor = b * std::sqrt(1.0 + eps);
  const Vec2 expected[4] = {{onMajor, 0}, {-onMajor, 0}, {0, onMinor}, {0, -onMinor}};
  for (const Vec2& e : expected) {
    // Start 10% off the answer; the solver must converge to the analytic position.
    const Vec2 theta =
        test::solveLensEquation(lens, {e[0] * 1.1 + 0.01, e[1] * 0.9 + 0.01}, {0, 0});
    EXPECT_NEAR(theta[0], e[0], 1e-10);
    EXPECT_NEAR(theta[1], e[1], 1e-10);
  }
}

TEST(EllipticalPotentialLens, RotatedLensRotatesItsImages) {
  const double b = 1.0, eps = 0.1, pa = 0.6;
  const EllipticalPotentialLens lens({b, eps, 0.0, pa});
  const double r = b * std::sqrt(1.0 - eps);
  const Vec2 start{r * std::cos(pa) * 1.05, r * std::sin(pa) * 0.95};
  const Vec2 theta = test::solveLensEquation(lens, start, {0, 0});
  EXPECT_NEAR(theta[0], r * std::cos(pa), 1e-10);
  EXPECT_NEAR(theta[1], r * std::sin(pa), 1e-10);
}

TEST(EllipticalPotentialLens, DeflectionIsTheGradientOfThePotential) {
  const EllipticalPotentialLens lens({1.4, 0.12, 0.05, 0.8});
  const double h = 1e-6;
  for (const Vec2 t : {Vec2{0.3, -0.7}, Vec2{-1.9, 0.4}, Vec2{2.5, 2.1}, Vec2{0.02, 0.01}}) {
    const double gx =
        (lens.potentialArcsec2({t[0] + h, t[1]}) - lens.potentialArcsec2({t[0] - h, t[1]})) /
        (2 * h);
    const double gy =
        (lens.potentialArcsec2({t[0], t[1] + h}) - lens.potentialArcsec2({t[0], t[1] - h})) /
        (2 * h);
    const Vec2 alpha = lens.deflectionArcsec(t);
    EXPECT_NEAR(alpha[0], gx, 1e-7);
    EXPECT_NEAR(alpha[1], gy, 1e-7);
    EXPECT_LE(std::hypot(alpha[0], alpha[1]), lens.maxDeflectionArcsec() + 1e-12);
  }
}

TEST(EllipticalPotentialLens, MagnificationMatchesFiniteDifferencesAndSis) {
  const EllipticalPotentialLens lens({1.2, 0.1, 0.03, 0.3});
  const Vec2 t{0.9, -0.8};
  const double h = 1e-6;
  const Vec2 bxp = lens.sourcePositionArcsec({t[0] + h, t[1]});
  const Vec2 bxm = lens.sourcePositionArcsec({t[0] - h, t[1]});
  const Vec2 byp = lens.sourcePositionArcsec({t[0], t[1] + h});
  const Vec2 bym = lens.sourcePositionArcsec({t[0], t[1] - h});
  const double det = (bxp[0] - bxm[0]) * (byp[1] - bym[1]) / (4 * h * h) -
                     (byp[0] - bym[0]) * (bxp[1] - bxm[1]) / (4 * h * h);
  EXPECT_NEAR(lens.magnification(t), 1.0 / det, 1e-5 * std::abs(1.0 / det));

  // SIS (eps = 0, no core): mu = |theta| / (|theta| - b).
  const EllipticalPotentialLens sis({1.5, 0.0, 0.0, 0.0});
  for (double r : {0.5, 1.2, 1.9, 3.0}) {
    EXPECT_NEAR(sis.magnification({r * 0.6, r * 0.8}), r / (r - 1.5), 1e-12);
  }
}

// Hand computation: sigma/c = 300/299792.458 = 1.0006923e-3; 4 pi (sigma/c)^2 = 1.2583776e-5 rad
// = 2.5955901"; D_ls/D_s = (D_C(1.5) - D_C(0.5))/D_C(1.5) = (4363.8558 - 1888.6254)/4363.8558
// = 0.5672118 (D_C from astropy FlatLambdaCDM(70, 0.3)); b = 2.5955901" x 0.5672118 = 1.472249".
TEST(EinsteinRadius, SisAtHalfAndOneAndAHalf) {
  const FlatLambdaCdm cosmo;
  EXPECT_NEAR(sisEinsteinRadiusArcsec(300.0, 0.5, 1.5, cosmo), 1.472249, 2e-6);
  // b scales as sigma^2.
  EXPECT_NEAR(sisEinsteinRadiusArcsec(150.0, 0.5, 1.5, cosmo), 1.472249 / 4.0, 1e-6);
  EXPECT_THROW(sisEinsteinRadiusArcsec(300.0, 1.5, 0.5, cosmo), ConfigError);
  EXPECT_THROW(sisEinsteinRadiusArcsec(-1.0, 0.5, 1.5, cosmo), ConfigError);
}

TEST(EllipticalPotentialLens, PotentialEllipticityFromLight) {
  EXPECT_DOUBLE_EQ(potentialEllipticityFromLight(0.0), 0.0);
  EXPECT_DOUBLE_EQ(potentialEllipticityFromLight(0.4), 0.2 * 0.4 / 1.0);
  EXPECT_LT(potentialEllipticityFromLight(0.999), 0.2);
  EXPECT_THROW(potentialEllipticityFromLight(1.0), ConfigError);
  EXPECT_THROW(EllipticalPotentialLens({0.0, 0.1, 0.0, 0.0}), ConfigError);
  EXPECT_THROW(EllipticalPotentialLens({1.0, 1.0, 0.0, 0.0}), ConfigError);
  EXPECT_THROW(EllipticalPotentialLens({1.0, 0.1, -0.1, 0.0}), ConfigError);
}

}  // namespace
}  // namespace octarc::simulation
