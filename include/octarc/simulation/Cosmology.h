// Flat Lambda-CDM distances (METHOD.md section 3). Radiation is neglected (it changes distances
// to z = 3 by less than 1e-4).
//
// Units: distances in Mpc, H0 in km/s/Mpc, the distance modulus in magnitudes.
#pragma once

#include <vector>

namespace octarc::simulation {

// Speed of light in km/s (exact, SI definition).
constexpr double kSpeedOfLightKmPerS = 299792.458;
// Arcseconds per radian.
constexpr double kArcsecPerRad = 180.0 * 3600.0 / 3.14159265358979323846;

struct CosmologyParams {
  double h0KmPerSPerMpc = 70.0;
  double omegaMatter = 0.3;
  double omegaLambda = 0.7;  // must equal 1 - omegaMatter: the model is flat
};

class FlatLambdaCdm {
 public:
  // Throws ConfigError (naming the parameter) unless H0 > 0, 0 <= Om and Om + OL == 1 (1e-6).
  explicit FlatLambdaCdm(const CosmologyParams& params = {});

  const CosmologyParams& params() const { return params_; }
  // Hubble distance c/H0.
  double hubbleDistanceMpc() const { return kSpeedOfLightKmPerS / params_.h0KmPerSPerMpc; }
  // E(z) = H(z)/H0 = sqrt(Om (1+z)^3 + OL).
  double hubbleRatio(double z) const;
  // Line-of-sight comoving distance D_C(z) = D_H * integral_0^z dz'/E(z'), by Gauss-Legendre
  // quadrature on panels of width <= 0.05 (relative error far below 1e-9 for 0 <= z <= 20).
  // For z <= kTabulatedMaxRedshift it is read from a table of those integrals at every 0.01,
  // made once by the constructor, by cubic Hermite interpolation with the exact derivative
  // D_H / E(z) (a relative difference below 1e-12 from the quadrature): the lens simulations
  // ask for several distances per drawn system.
  double comovingDistanceMpc(double z) const;
  // The same by quadrature alone (what the table holds, and z beyond it).
  double comovingDistanceByQuadratureMpc(double z) const;
  static constexpr double kTabulatedMaxRedshift = 10.0;
  // D_A(z) = D_C(z) / (1 + z) (flat universe).
  double angularDiameterDistanceMpc(double z) const;
  // D_A(z1, z2) = (D_C(z2) - D_C(z1)) / (1 + z2) for z1 <= z2 (flat universe).
  double angularDiameterDistanceMpc(double z1, double z2) const;
  // D_L(z) = (1 + z) D_C(z).
  double luminosityDistanceMpc(double z) const;
  // 5 log10(D_L / 10 pc).
  double distanceModulusMag(double z) const;
  // Comoving volume per unit redshift and solid angle, dV_C / dz / dOmega = D_H D_C^2 / E(z)
  // (flat universe), in Mpc^3 per steradian.
  double comovingVolumePerRedshiftMpc3PerSr(double z) const;

 private:
  static constexpr double kTableStep = 0.01;
  CosmologyParams params_;
  std::vector<double> tableMpc_;  // D_C at z = k * kTableStep
};

}  // namespace octarc::simulation
