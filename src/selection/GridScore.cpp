#include "octarc/selection/GridScore.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {

std::vector<RowScore> scoreSamples(const OccupationGrid& grid, const Contour& contour,
                                   const AxisSamples& samples) {
  const GridBinning& binning = grid.binning();
  const std::size_t dims = std::size_t(binning.dimensions());
  if (samples.size() != dims) {
    throw ConfigError("scoring against a grid of " + std::to_string(dims) + " axes with " +
                      std::to_string(samples.size()) + " axes of values");
  }
  const std::size_t n = samples.empty() ? 0 : samples[0].size();
  std::vector<RowScore> scores(n);
  std::vector<int> k(dims);
  for (std::size_t i = 0; i < n; ++i) {
    RowScore& s = scores[i];
    s.entryLevel = std::numeric_limits<double>::quiet_NaN();
    bool isNan = false;
    bool isOutside = false;
    for (std::size_t a = 0; a < dims; ++a) {
      isNan = isNan || std::isnan(samples[a][i]);
      k[a] = binning.binOf(int(a), samples[a][i]);
      isOutside = isOutside || k[a] < 0;
    }
    if (isNan || isOutside) {
      s.status = isNan ? ScoreStatus::Undefined : ScoreStatus::Outside;
      continue;
    }
    s.rank = grid.rankOf(binning.pack(k));
    if (s.rank < 0) {
      s.status = ScoreStatus::EmptyBin;
      continue;
    }
    const GridBin& bin = grid.bins()[std::size_t(s.rank)];
    s.status = ScoreStatus::OccupiedBin;
    s.probability = bin.probability;
    s.entryLevel = bin.cumulative;
    s.selected = contour.selects(s.rank);
  }
  return scores;
}

std::vector<RowScore> scoreRows(const OccupationGrid& grid, const Contour& contour,
                                const Table& catalog) {
  std::vector<std::string> expressions;
  for (const GridAxis& axis : grid.binning().axes()) expressions.push_back(axis.expression);
  return scoreSamples(grid, contour, evaluateAxes(expressions, catalog));
}

}  // namespace octarc
