#include "octarc/calibration/Weights.h"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <cmath>
#include <cstdio>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc {

std::vector<double> systemWeights(const Table& systems) {
  std::vector<double> w(std::size_t(systems.rows()), 1.0);
  const int column = systems.findColumn(kWeightColumn);
  if (column < 0) return w;
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    const double v = systems.value(r, column);
    w[std::size_t(r)] = std::isfinite(v) && v > 0.0 ? v : 0.0;
  }
  return w;
}

FractionInterval clopperPearson(double k, double n, double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw ConfigError("binomial interval: confidence " + formatNumber(confidence, "%.6g") +
                      " outside (0, 1)");
  }
  FractionInterval out;
  if (!(n > 0.0)) return out;
  if (!(k >= 0.0) || k > n * (1.0 + 1e-12)) {
    throw ConfigError("binomial interval: " + formatNumber(k, "%.6g") + " successes in " +
                      formatNumber(n, "%.6g") + " trials");
  }
  k = std::min(k, n);
  using Binomial = boost::math::binomial_distribution<double>;
  const double tail = 0.5 * (1.0 - confidence);
  out.fraction = k / n;
  out.lo = k > 0.0 ? Binomial::find_lower_bound_on_p(n, k, tail) : 0.0;
  out.hi = k < n ? Binomial::find_upper_bound_on_p(n, k, tail) : 1.0;
  // Rounding must not leave the fraction outside its own interval.
  out.lo = std::min(out.lo, out.fraction);
  out.hi = std::max(out.hi, out.fraction);
  return out;
}

FractionInterval weightedFractionInterval(double fraction, double n, double confidence) {
  if (!(n > 0.0)) {
    FractionInterval out;
    out.fraction = fraction;
    out.lo = std::min(0.0, fraction);
    out.hi = std::max(1.0, fraction);
    return out;
  }
  FractionInterval out = clopperPearson(std::clamp(fraction, 0.0, 1.0) * n, n, confidence);
  out.fraction = fraction;  // exactly the weighted fraction, not k / n rounded
  out.lo = std::min(out.lo, fraction);
  out.hi = std::max(out.hi, fraction);
  return out;
}

std::string countWithEffective(std::int64_t count, double effective, const std::string& noun) {
  return std::to_string(count) + " " + noun + " (" + formatNumber(effective, "%.0f") +
         " effective)";
}

std::string intervalText(const FractionInterval& f) {
  char text[64];
  std::snprintf(text, sizeof text, "+%.4f -%.4f", f.hi - f.fraction, f.fraction - f.lo);
  return text;
}

}  // namespace octarc
