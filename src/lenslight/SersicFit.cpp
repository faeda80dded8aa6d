#include "octarc/lenslight/SersicFit.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace octarc::lenslight {

namespace {

// A rank-deficient covariance (a round galaxy has no position angle) leaves the errors NaN, and
// Ceres would also log it through glog on stderr, once per galaxy: glog is quieted below FATAL,
// at start-up, before any thread runs.
[[maybe_unused]] const bool kGlogQuiet = [] {
  FLAGS_minloglevel = google::GLOG_FATAL;
  return true;
}();

// The fitted parameters: x, y, log flux, log radius, index, axis ratio, angle. Logarithms keep
// flux and radius positive and their steps relative.
constexpr int kParams = 7;

double wrapAngle(double theta) {
  // The major axis is a direction: angles modulo pi, in [0, pi).
  theta = std::fmod(theta, std::numbers::pi);
  return theta < 0 ? theta + std::numbers::pi : theta;
}

// The axis ratio is fitted on (0, 1 / minAxisRatio]: q > 1 is the same ellipse with its axes
// swapped (q' = 1/q, r_e' = q r_e, theta' = theta + pi/2, same I_e), so the model is smooth
// through q = 1 and a round galaxy sits inside the bounds, where the numerical derivatives can
// step both ways.
SersicParams fromVector(const double* p) {
  SersicParams s;
  s.xPix = p[0];
  s.yPix = p[1];
  s.totalFluxAdu = std::exp(p[2]);
  s.halfLightRadiusPix = std::exp(p[3]);
  s.sersicIndex = p[4];
  s.axisRatio = p[5];
  s.positionAngleRad = p[6];
  if (s.axisRatio > 1.0) {
    s.halfLightRadiusPix *= s.axisRatio;
    s.axisRatio = 1.0 / s.axisRatio;
    s.positionAngleRad += 0.5 * std::numbers::pi;
  }
  s.positionAngleRad = wrapAngle(s.positionAngleRad);
  return s;
}

// All pixel residuals (stamp - model) / sigma in one block: the model is drawn and convolved as
// a whole, so its derivatives are taken numerically (central differences).
struct StampResiduals {
  const ImageD* stamp;
  std::vector<std::int64_t> pixels;  // the fitted pixels' linear indices
  std::vector<double> inverseSigma;
  double psfSigmaPix;
  double robustScale;  // SersicFitSettings::robustScaleSigma

  // The residual whose square is the one-sided robust cost: Ceres minimises the sum of
  // squares, and the numerical derivatives follow the transform.
  double robust(double r) const {
    if (!(robustScale > 0.0) || r <= 0.0) return r;
    const double u = r / robustScale;
    return robustScale * std::sqrt(std::log1p(u * u));
  }

  bool operator()(double const* const* parameters, double* residuals) const {
    for (int i = 0; i < kParams; ++i) {
      if (!std::isfinite(parameters[0][i])) return false;
    }
    const SersicParams s = fromVector(parameters[0]);
    // Inside the bounds always true; a step outside them is refused, never thrown.
    if (!(s.axisRatio > 0.0) || !(s.sersicIndex > 0.0) || !(s.halfLightRadiusPix > 0.0)) {
      return false;
    }
    const ImageD model = renderSersic(s, int(stamp->width()), int(stamp->height()), psfSigmaPix);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      const std::int64_t p = pixels[i];
      residuals[i] = robust(((*stamp)[p] - model[p]) * inverseSigma[i]);
    }
    return true;
  }
};

}  // namespace

SersicParams momentsStart(const ImageD& stamp) {
  double sum = 0, sx = 0, sy = 0;
  for (std::int64_t y = 0; y < stamp.height(); ++y) {
    for (std::int64_t x = 0; x < stamp.width(); ++x) {
      const double v = stamp(x, y);
      if (!(v > 0)) continue;
      sum += v;
      sx += v * double(x);
      sy += v * double(y);
    }
  }
  SersicParams s;
  s.sersicIndex = 2.5;
  if (!(sum > 0)) return s;
  s.xPix = sx / sum;
  s.yPix = sy / sum;
  double xx = 0, yy = 0, xy = 0;
  for (std::int64_t y = 0; y < stamp.height(); ++y) {
    for (std::int64_t x = 0; x < stamp.width(); ++x) {
      const double v = stamp(x, y);
      if (!(v > 0)) continue;
      const double dx = double(x) - s.xPix, dy = double(y) - s.yPix;
      xx += v * dx * dx;
      yy += v * dy * dy;
      xy += v * dx * dy;
    }
  }
  xx /= sum;
  yy /= sum;
  xy /= sum;
  const double mean = 0.5 * (xx + yy), diff = 0.5 * (xx - yy);
  const double root = std::sqrt(diff * diff + xy * xy);
  const double a2 = mean + root, b2 = std::max(mean - root, 1e-6);
  s.totalFluxAdu = sum;
  s.axisRatio = std::clamp(std::sqrt(b2 / a2), 0.1, 1.0);
  s.positionAngleRad = wrapAngle(0.5 * std::atan2(2.0 * xy, xx - yy));
  // The moments of noisy wings overestimate the size; half of it is a safe start.
  s.halfLightRadiusPix = std::max(0.5 * std::sqrt(a2), 0.5);
  return s;
}

SersicFitResult fitSersic(const ImageD& stamp, const ImageD& varianceAdu2,
                          const std::vector<std::uint8_t>& ignored, const SersicParams& start,
                          const SersicFitSettings& settings) {
  auto* residuals =
      new StampResiduals{&stamp, {}, {}, settings.psfSigmaPix, settings.robustScaleSigma};
  for (std::int64_t p = 0; p < stamp.size(); ++p) {
    const double var = varianceAdu2[p];
    if (!ignored.empty() && ignored[std::size_t(p)] != 0) continue;
    if (!(var > 0.0) || !std::isfinite(var) || !std::isfinite(stamp[p])) continue;
    residuals->pixels.push_back(p);
    residuals->inverseSigma.push_back(1.0 / std::sqrt(var));
  }
  SersicFitResult out;
  const std::int64_t used = std::int64_t(residuals->pixels.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.errors = {nan, nan, nan, nan, nan, nan, nan};
  if (used <= kParams) {
    delete residuals;
    out.params = start;
    out.message = kTooFewPixelsMessage;
    return out;
  }
  const double size = double(std::max(stamp.width(), stamp.height()));
  const double maxRadiusPix = std::max(0.5 * size, settings.minHalfLightRadiusPix * 2.0);
  double p[kParams] = {
      start.xPix,
      start.yPix,
      std::log(start.totalFluxAdu),
      std::log(std::clamp(start.halfLightRadiusPix, settings.minHalfLightRadiusPix, maxRadiusPix)),
      std::clamp(start.sersicIndex, settings.minIndex, settings.maxIndex),
      std::clamp(start.axisRatio, settings.minAxisRatio, 1.0),
      start.positionAngleRad};
  ceres::NumericDiffOptions diff;
  diff.relative_step_size = 1e-5;
  auto* cost = new ceres::DynamicNumericDiffCostFunction<StampResiduals, ceres::FORWARD>(
      residuals, ceres::TAKE_OWNERSHIP, diff);
  cost->AddParameterBlock(kParams);
  cost->SetNumResiduals(int(used));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, p);
  problem.SetParameterLowerBound(p, 3, std::log(settings.minHalfLightRadiusPix));
  problem.SetParameterUpperBound(p, 3, std::log(maxRadiusPix));
  problem.SetParameterLowerBound(p, 4, settings.minIndex);
  problem.SetParameterUpperBound(p, 4, settings.maxIndex);
  problem.SetParameterLowerBound(p, 5, settings.minAxisRatio);
  problem.SetParameterUpperBound(p, 5, 1.0 / settings.minAxisRatio);

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = settings.maxIterations;
  // Far below the parameters' errors (a relative change of 1e-7 of the cost is a change of chi^2
  // of 1e-7 per pixel, where one sigma is a change of 1 in all), and reached in a few iterations
  // where 1e-12 ran to the limit on noise.
  options.function_tolerance = 1e-7;
  options.parameter_tolerance = 1e-7;
  options.gradient_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.iterations = int(summary.iterations.size());
  if (!out.converged) out.message = summary.BriefReport();
  out.chi2 = 2.0 * summary.final_cost;
  out.degreesOfFreedom = used - kParams;
  out.params = fromVector(p);
  constexpr double kAtBound = 1e-3;  // in log radius: 0.1 %
  out.radiusAtLimit = p[3] < std::log(settings.minHalfLightRadiusPix) + kAtBound ||
                      p[3] > std::log(maxRadiusPix) - kAtBound;
  out.shapeAtBound = p[4] < settings.minIndex * (1.0 + kAtBound) ||
                     p[4] > settings.maxIndex * (1.0 - kAtBound) ||
                     p[5] < settings.minAxisRatio * (1.0 + kAtBound) ||
                     p[5] > (1.0 - kAtBound) / settings.minAxisRatio;
  // A robust fit is a start for the masked one (LensLightSettings), whose errors are the ones
  // reported: its own would cost another Jacobian.
  if (!summary.IsSolutionUsable() || settings.robustScaleSigma > 0.0) return out;

  ceres::Covariance::Options covarianceOptions;
  covarianceOptions.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(covarianceOptions);
  const std::vector<std::pair<const double*, const double*>> blocks = {{p, p}};
  double c[kParams * kParams];
  if (covariance.Compute(blocks, &problem) && covariance.GetCovarianceBlock(p, p, c)) {
    auto var = [&](int i, int j) { return c[i * kParams + j]; };
    auto root = [](double v) {
      return v >= 0.0 ? std::sqrt(v) : std::numeric_limits<double>::quiet_NaN();
    };
    out.errors.xPix = root(var(0, 0));
    out.errors.yPix = root(var(1, 1));
    out.errors.totalFluxAdu = out.params.totalFluxAdu * root(var(2, 2));
    out.errors.sersicIndex = root(var(4, 4));
    out.errors.positionAngleRad = root(var(6, 6));
    const double q = p[5];
    if (q > 1.0) {
      // Through the swap of axes: log r_e' = log r_e + log q, q' = 1/q.
      out.errors.halfLightRadiusPix = out.params.halfLightRadiusPix *
                                      root(var(3, 3) + var(5, 5) / (q * q) + 2.0 * var(3, 5) / q);
      out.errors.axisRatio = root(var(5, 5)) / (q * q);
    } else {
      out.errors.halfLightRadiusPix = out.params.halfLightRadiusPix * root(var(3, 3));
      out.errors.axisRatio = root(var(5, 5));
    }
  }
  return out;
}

LensLightModel fitLensLight(const ImageD& stamp, const ImageD& varianceAdu2,
                            const LensLightSettings& settings) {
  return fitLensLightFrom(stamp, varianceAdu2, momentsStart(stamp), settings);
}

LensLightModel fitLensLightFrom(const ImageD& stamp, const ImageD& varianceAdu2,
                                const SersicParams& firstStart, const LensLightSettings& settings) {
  LensLightModel out;
  out.clipped.assign(std::size_t(stamp.size()), 0);
  SersicParams start = firstStart;
  const std::int64_t w = stamp.width(), h = stamp.height();
  SersicFitSettings robust = settings.fit;
  robust.robustScaleSigma = settings.robustScaleSigma;
  robust.maxIterations = std::min(settings.fit.maxIterations, settings.robustMaxIterations);
  for (int round = 0;; ++round) {
    out.fit =
        fitSersic(stamp, varianceAdu2, out.clipped, start, round == 0 ? robust : settings.fit);
    out.model = renderSersic(out.fit.params, int(w), int(h), settings.fit.psfSigmaPix);
    out.residual = stamp;
    for (std::int64_t p = 0; p < stamp.size(); ++p) out.residual[p] -= out.model[p];
    if (round == settings.clipRounds) break;
    // Positive outliers, the residual over its noise averaged on 3 x 3 pixels (so that an arc's
    // faint edges go with it, and single noise peaks stay), grown by a pixel.
    std::vector<std::uint8_t> above(std::size_t(stamp.size()), 0);
    for (std::int64_t y = 0; y < h; ++y) {
      for (std::int64_t x = 0; x < w; ++x) {
        double sum = 0, var = 0;
        int count = 0;
        for (std::int64_t v = std::max<std::int64_t>(y - 1, 0); v <= std::min(y + 1, h - 1); ++v) {
          for (std::int64_t u = std::max<std::int64_t>(x - 1, 0); u <= std::min(x + 1, w - 1);
               ++u) {
            const double r = out.residual(u, v), s2 = varianceAdu2(u, v);
            if (!std::isfinite(r) || !(s2 > 0) || !std::isfinite(s2)) continue;
            sum += r;
            var += s2;
            ++count;
          }
        }
        if (count > 0 && sum > settings.clipSigma * std::sqrt(var)) {
          above[std::size_t(y * w + x)] = 1;
        }
      }
    }
    std::vector<std::uint8_t> next(std::size_t(stamp.size()), 0);
    for (std::int64_t y = 0; y < h; ++y) {
      for (std::int64_t x = 0; x < w; ++x) {
        if (!above[std::size_t(y * w + x)]) continue;
        for (std::int64_t v = std::max<std::int64_t>(y - 1, 0); v <= std::min(y + 1, h - 1); ++v) {
          for (std::int64_t u = std::max<std::int64_t>(x - 1, 0); u <= std::min(x + 1, w - 1);
               ++u) {
            next[std::size_t(v * w + u)] = 1;
          }
        }
      }
    }
    // The robust fit is always followed by a plain one (its errors); a plain fit whose mask
    // stays the same is done.
    const bool robustRound = round == 0 && settings.robustScaleSigma > 0.0;
    if (next == out.clipped && !robustRound) break;
    out.clipped = std::move(next);
    start = out.fit.params;
  }
  return out;
}

}  // namespace octarc::lenslight
