// A Gaussian fitted to a histogram, for the widths of the skewness distributions (METHOD.md
// section 3: s_a and s_b of the arcs with arcness above 0.10, with the FWHM of a Gaussian fit).
//
// The model A exp(-(x - mu)^2 / (2 sigma^2)) is fitted to the bin values at the bin centres by
// unweighted least squares (Ceres Solver, Levenberg-Marquardt), starting from the histogram's
// peak, mean and standard deviation; FWHM = 2 sqrt(2 ln 2) sigma.
#pragma once

#include <vector>

namespace octarc {

struct GaussianFit {
  double amplitude = 0, mean = 0, sigma = 0, fwhm = 0;  // NaN when there is nothing to fit
  bool converged = false;
};

// Bin edges (n + 1, increasing) and values (n). Fewer than three non-empty bins: NaN, not
// converged.
GaussianFit fitGaussian(const std::vector<double>& edges, const std::vector<double>& values);

}  // namespace octarc
