#include "octarc/simulation/Cosmology.h"

#include <array>
#include <cmath>
#include <string>

#include "octarc/core/Error.h"

namespace octarc::simulation {

namespace {

// 8-point Gauss-Legendre nodes and weights on [-1, 1] (positive half; symmetric).
constexpr std::array<double, 4> kGlNodes = {0.1834346424956498, 0.5255324099163290,
                                            0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> kGlWeights = {0.3626837833783620, 0.3137066458778873,
                                              0.2223810344533745, 0.1012285362903763};
constexpr double kMaxPanelWidth = 0.05;

}  // namespace

FlatLambdaCdm::FlatLambdaCdm(const CosmologyParams& params) : params_(params) {
  if (!(params.h0KmPerSPerMpc > 0.0) || !std::isfinite(params.h0KmPerSPerMpc))
    throw ConfigError("cosmology: H0 must be positive, got " +
                      std::to_string(params.h0KmPerSPerMpc));
  if (!(params.omegaMatter >= 0.0) || !std::isfinite(params.omegaMatter))
    throw ConfigError("cosmology: Omega_m must be >= 0, got " + std::to_string(params.omegaMatter));
  if (std::abs(params.omegaMatter + params.omegaLambda - 1.0) > 1e-6)
    throw ConfigError("cosmology: Omega_m + Omega_Lambda must be 1 (flat model), got " +
                      std::to_string(params.omegaMatter + params.omegaLambda));
  const int nodes = int(std::lround(kTabulatedMaxRedshift / kTableStep)) + 1;
  tableMpc_.reserve(std::size_t(nodes));
  for (int k = 0; k < nodes; ++k)
    tableMpc_.push_back(comovingDistanceByQuadratureMpc(k * kTableStep));
}

double FlatLambdaCdm::hubbleRatio(double z) const {
  const double a = 1.0 + z;
  return std::sqrt(params_.omegaMatter * a * a * a + params_.omegaLambda);
}

double FlatLambdaCdm::comovingDistanceMpc(double z) const {
  if (!(z >= 0.0) || !(z < kTabulatedMaxRedshift) || tableMpc_.empty()) {
    return comovingDistanceByQuadratureMpc(z);
  }
  // Cubic Hermite on [z0, z0 + h], with the derivative D_H / E at both nodes.
  const auto k = std::size_t(z / kTableStep);
  const double h = kTableStep, z0 = double(k) * h, t = (z - z0) / h;
  const double d0 = hubbleDistanceMpc() / hubbleRatio(z0);
  const double d1 = hubbleDistanceMpc() / hubbleRatio(z0 + h);
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * tableMpc_[k] + (t3 - 2 * t2 + t) * h * d0 +
         (-2 * t3 + 3 * t2) * tableMpc_[k + 1] + (t3 - t2) * h * d1;
}

double FlatLambdaCdm::comovingDistanceByQuadratureMpc(double z) const {
  if (!(z >= 0.0) || !std::isfinite(z))
    throw ConfigError("cosmology: redshift must be finite and >= 0, got " + std::to_string(z));
  if (z == 0.0) return 0.0;
  const int panels = static_cast<int>(std::ceil(z / kMaxPanelWidth));
  const double width = z / panels;
  double integral = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double mid = (p + 0.5) * width;
    const double half = 0.5 * width;
    double panel = 0.0;
    for (std::size_t k = 0; k < kGlNodes.size(); ++k) {
      panel += kGlWeights[k] * (1.0 / hubbleRatio(mid - half * kGlNodes[k]) +
                                1.0 / hubbleRatio(mid + half * kGlNodes[k]));
    }
    integral += panel * half;
  }
  return hubbleDistanceMpc() * integral;
}

double FlatLambdaCdm::angularDiameterDistanceMpc(double z) const {
  return comovingDistanceMpc(z) / (1.0 + z);
}

double FlatLambdaCdm::angularDiameterDistanceMpc(double z1, double z2) const {
  if (z2 < z1)
    throw ConfigError("cosmology: D_A(z1, z2) needs z1 <= z2, got " + std::to_string(z1) + ", " +
                      std::to_string(z2));
  return (comovingDistanceMpc(z2) - comovingDistanceMpc(z1)) / (1.0 + z2);
}

double FlatLambdaCdm::luminosityDistanceMpc(double z) const {
  return comovingDistanceMpc(z) * (1.0 + z);
}

double FlatLambdaCdm::distanceModulusMag(double z) const {
  // D_L in units of 10 pc = D_L[Mpc] * 1e5.
  return 5.0 * std::log10(luminosityDistanceMpc(z) * 1e5);
}

double FlatLambdaCdm::comovingVolumePerRedshiftMpc3PerSr(double z) const {
  const double dc = comovingDistanceMpc(z);
  return hubbleDistanceMpc() * dc * dc / hubbleRatio(z);
}

}  // namespace octarc::simulation
