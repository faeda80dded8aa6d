// The weights of simulated systems and the exact binomial intervals of the fractions made from
// them.
//
// simulate lenses renders only some of the systems it draws (importance sampling); each
// rendered row stands for SIM_WEIGHT = 1 / (its render probability) systems of the population,
// so every fraction or distribution of the population is a weighted one. Outputs without the
// column (older ones, or simulations of one's own) weigh every row 1.
//
// How many arcs a weighted sample is worth: the Kish effective number (sum w)^2 / sum w^2, equal
// to the count when every weight is the same. Reported beside the count ("496 arcs (412
// effective)").
//
// Intervals: Clopper-Pearson (exact binomial, central) at 68.27 % (1 sigma), Boost.Math's
// binomial_distribution bounds. For weighted data the trials are the Kish effective number n of
// the normalising rows and the successes k = f n, f the weighted fraction (both may be
// non-integer). So 0 of N has a non-zero upper bound, N of N a lower bound below 1.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"

namespace octarc {

// The column of the systems table holding the weights.
inline constexpr const char* kWeightColumn = "SIM_WEIGHT";

// SIM_WEIGHT of every row of `systems`, or 1 for every row when the table has no such column. A
// weight that is not finite and positive is a row that stands for nothing: weight 0.
std::vector<double> systemWeights(const Table& systems);

// A weighted count: rows, sum of weights, sum of squared weights.
struct WeightedCount {
  std::int64_t count = 0;
  double weightSum = 0.0, weightSquaredSum = 0.0;
  void add(double weight) {
    ++count;
    weightSum += weight;
    weightSquaredSum += weight * weight;
  }
  // Kish's effective number (sum w)^2 / sum w^2; 0 for no weight.
  double effective() const {
    return weightSquaredSum > 0.0 ? weightSum * weightSum / weightSquaredSum : 0.0;
  }
};

// The confidence of the intervals: 1 sigma two-sided, 68.27 %.
inline constexpr double kOneSigmaConfidence = 0.6827;

struct FractionInterval {
  double fraction = 0.0;  // k / n (0 for n = 0)
  double lo = 0.0;        // the interval's bounds, lo <= fraction <= hi
  double hi = 1.0;
  double halfWidth() const { return 0.5 * (hi - lo); }
};

// Clopper-Pearson interval of k successes in n trials (both real, 0 <= k <= n) at `confidence`
// (two-sided, central). n <= 0 gives fraction 0 on [0, 1] (nothing known). ConfigError for
// k < 0, k > n or a confidence outside (0, 1).
FractionInterval clopperPearson(double successes, double trials,
                                double confidence = kOneSigmaConfidence);

// The interval of a weighted fraction `fraction` of rows whose Kish effective number is
// `effectiveTrials` (k = fraction x n).
FractionInterval weightedFractionInterval(double fraction, double effectiveTrials,
                                          double confidence = kOneSigmaConfidence);

// "496 arcs (412 effective)" (the effective number rounded); `noun` is the plural ("arcs",
// "systems").
std::string countWithEffective(std::int64_t count, double effective,
                               const std::string& noun = "arcs");

// "+0.0764 -0.0000": the interval around its fraction, 4 decimals.
std::string intervalText(const FractionInterval& interval);

}  // namespace octarc
