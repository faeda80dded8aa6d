#include "octarc/calibration/GaussianFit.h"

#include <ceres/ceres.h>

#include <cmath>

#include "octarc/core/Conventions.h"

namespace octarc {

namespace {

// One bin's residual: model at the bin centre minus the bin value.
struct GaussianResidual {
  double x, y;
  template <typename T>
  bool operator()(const T* const p, T* residual) const {
    const T d = (T(x) - p[1]) / p[2];
    residual[0] = p[0] * exp(T(-0.5) * d * d) - T(y);
    return true;
  }
};

}  // namespace

GaussianFit fitGaussian(const std::vector<double>& edges, const std::vector<double>& values) {
  GaussianFit fit;
  fit.amplitude = fit.mean = fit.sigma = fit.fwhm = std::nan("");
  if (edges.size() != values.size() + 1) return fit;
  // The starting point: the peak, and the mean and standard deviation of the binned values
  // (about the first non-empty bin's centre, a local origin).
  double sum = 0, peak = 0, m1 = 0, m2 = 0, origin = std::nan("");
  int nonEmpty = 0;
  std::vector<double> centres;
  for (std::size_t k = 0; k < values.size(); ++k) {
    centres.push_back(0.5 * (edges[k] + edges[k + 1]));
    if (!(values[k] > 0)) continue;
    if (nonEmpty++ == 0) origin = centres[k];
    const double dx = centres[k] - origin;
    sum += values[k];
    m1 += values[k] * dx;
    m2 += values[k] * dx * dx;
    peak = std::max(peak, values[k]);
  }
  if (nonEmpty < 3) return fit;
  m1 /= sum;
  double p[3] = {peak, origin + m1, std::sqrt(std::max(m2 / sum - m1 * m1, 1e-300))};

  ceres::Problem problem;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<GaussianResidual, 1, 3>(
                                 new GaussianResidual{centres[k], values[k]}),
                             nullptr, p);
  }
  problem.SetParameterLowerBound(p, 2, 1e-12 * (edges.back() - edges.front()));
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 200;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.amplitude = p[0];
  fit.mean = p[1];
  fit.sigma = std::abs(p[2]);
  fit.fwhm = kGaussianFwhmPerSigma * fit.sigma;
  return fit;
}

}  // namespace octarc
