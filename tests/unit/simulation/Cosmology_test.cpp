#include "octarc/simulation/Cosmology.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc::simulation {
namespace {

// Values printed by astropy 5.2.1, FlatLambdaCDM(H0=70, Om0=0.3) (Tcmb0 = 0, no radiation):
// comoving_distance, angular_diameter_distance, distmod at z = 0.5, 1.5, 3.0, and
// angular_diameter_distance_z1z2(0.5, 1.5).
TEST(FlatLambdaCdm, MatchesAstropyPublishedValues) {
  const FlatLambdaCdm cosmo;
  EXPECT_NEAR(cosmo.comovingDistanceMpc(0.5) / 1888.62539593342, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.comovingDistanceMpc(1.5) / 4363.855766233609, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.comovingDistanceMpc(3.0) / 6355.685436297468, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.angularDiameterDistanceMpc(0.5) / 1259.0835972889465, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.angularDiameterDistanceMpc(1.5) / 1745.5423064934434, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.angularDiameterDistanceMpc(3.0) / 1588.921359074367, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.angularDiameterDistanceMpc(0.5, 1.5) / 990.0921481200755, 1.0, 1e-6);
  EXPECT_NEAR(cosmo.distanceModulusMag(0.5), 42.2611854215409, 1e-5);
  EXPECT_NEAR(cosmo.distanceModulusMag(1.5), 45.189051982817944, 1e-5);
  EXPECT_NEAR(cosmo.distanceModulusMag(3.0), 47.026111928689645, 1e-5);
}

// The same comparison, computed by astropy at test time for other parameters.
TEST(FlatLambdaCdm, MatchesAstropyAtTestTime) {
  std::string out;
  // Only a missing astropy is a reason to skip; once it imports, the script must run.
  if (test::runCommand("/usr/bin/python3 -c 'import astropy.cosmology' 2>&1", &out) != 0)
    OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available: " << out;
  const int status = test::runCommand(
      "/usr/bin/python3 -c \"from astropy.cosmology import FlatLambdaCDM as F\n"
      "c = F(H0=65, Om0=0.25)\n"
      "for z in (0.1, 0.7, 2.2, 5.0): print(c.comoving_distance(z).value, "
      "c.angular_diameter_distance(z).value, c.distmod(z).value)\n"
      "print(c.angular_diameter_distance_z1z2(0.7, 2.2).value)\"",
      &out);
  ASSERT_EQ(status, 0) << "the astropy script failed (its error is on stderr); output: " << out;
  std::istringstream in(out);
  const FlatLambdaCdm cosmo({65.0, 0.25, 0.75});
  for (double z : {0.1, 0.7, 2.2, 5.0}) {
    double dc = 0, da = 0, dm = 0;
    ASSERT_TRUE(in >> dc >> da >> dm);
    EXPECT_NEAR(cosmo.comovingDistanceMpc(z) / dc, 1.0, 1e-6) << "z " << z;
    EXPECT_NEAR(cosmo.angularDiameterDistanceMpc(z) / da, 1.0, 1e-6) << "z " << z;
    EXPECT_NEAR(cosmo.distanceModulusMag(z), dm, 1e-5) << "z " << z;
  }
  double da12 = 0;
  ASSERT_TRUE(in >> da12);
  EXPECT_NEAR(cosmo.angularDiameterDistanceMpc(0.7, 2.2) / da12, 1.0, 1e-6);
}

// Einstein-de Sitter (Om = 1): D_C = 2 D_H (1 - 1/sqrt(1+z)) (Hogg 1999, eq. 16 limit).
TEST(FlatLambdaCdm, EinsteinDeSitterAnalytic) {
  const FlatLambdaCdm eds({70.0, 1.0, 0.0});
  const double dh = kSpeedOfLightKmPerS / 70.0;
  for (double z : {0.01, 0.5, 1.0, 3.0, 10.0}) {
    const double expected = 2.0 * dh * (1.0 - 1.0 / std::sqrt(1.0 + z));
    EXPECT_NEAR(eds.comovingDistanceMpc(z) / expected, 1.0, 1e-10) << "z " << z;
  }
  // Pure Lambda (Om = 0): E = 1, D_C = D_H z.
  const FlatLambdaCdm desitter({70.0, 0.0, 1.0});
  EXPECT_NEAR(desitter.comovingDistanceMpc(2.0), 2.0 * dh, 1e-9 * dh);
  EXPECT_EQ(eds.comovingDistanceMpc(0.0), 0.0);
}

TEST(FlatLambdaCdm, DistanceRatioDoesNotDependOnH0) {
  const FlatLambdaCdm a({70.0, 0.3, 0.7});
  const FlatLambdaCdm b({100.0, 0.3, 0.7});
  EXPECT_NEAR(a.angularDiameterDistanceMpc(0.4, 1.2) / a.angularDiameterDistanceMpc(1.2),
              b.angularDiameterDistanceMpc(0.4, 1.2) / b.angularDiameterDistanceMpc(1.2), 1e-12);
}

TEST(FlatLambdaCdm, RejectsBadParameters) {
  EXPECT_THROW(FlatLambdaCdm({70.0, 0.3, 0.6}), ConfigError);  // not flat
  EXPECT_THROW(FlatLambdaCdm({0.0, 0.3, 0.7}), ConfigError);
  EXPECT_THROW(FlatLambdaCdm({70.0, -0.1, 1.1}), ConfigError);
  const FlatLambdaCdm c;
  EXPECT_THROW(c.comovingDistanceMpc(-1.0), ConfigError);
  EXPECT_THROW(c.angularDiameterDistanceMpc(1.0, 0.5), ConfigError);
  try {
    FlatLambdaCdm({70.0, 0.3, 0.6});
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("Omega_m + Omega_Lambda"), std::string::npos);
  }
}

TEST(FlatLambdaCdm, VolumeElementIsTheDerivativeOfTheComovingVolume) {
  // V_C(z) per steradian = D_C^3 / 3 in a flat universe.
  const FlatLambdaCdm c;
  for (double z : {0.1, 0.5, 1.2, 2.5}) {
    const double h = 1e-5;
    const double vp = std::pow(c.comovingDistanceMpc(z + h), 3) / 3.0;
    const double vm = std::pow(c.comovingDistanceMpc(z - h), 3) / 3.0;
    EXPECT_NEAR(c.comovingVolumePerRedshiftMpc3PerSr(z) / ((vp - vm) / (2 * h)), 1.0, 1e-7) << z;
  }
}

}  // namespace
}  // namespace octarc::simulation
