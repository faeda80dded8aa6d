#include "octarc/selection/BinningSearch.h"

#include <cstdio>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/selection/OccupationGrid.h"

namespace octarc {

int BinningSearchResult::requireFinest() const {
  if (finestConnected > 0) return finestConnected;
  char level[32];
  std::snprintf(level, sizeof level, "%.6g", options.level);
  throw ConfigError("no binning from " + std::to_string(options.minBins) + " to " +
                    std::to_string(options.maxBins) +
                    " bins per axis keeps the contour at P = " + level + " connected");
}

BinningSearchResult findFinestConnectedBinning(const std::vector<GridAxis>& axes,
                                               const AxisSamples& samples,
                                               const BinningSearchOptions& options,
                                               const std::vector<double>& weights) {
  if (options.minBins < 1 || options.maxBins < options.minBins) {
    throw ConfigError("binning search: bins per axis from " + std::to_string(options.minBins) +
                      " to " + std::to_string(options.maxBins) + " is not a range of at least 1");
  }
  const GridBinning base(axes);
  BinningSearchResult result;
  result.options = options;
  for (int n = options.minBins; n <= options.maxBins; ++n) {
    const OccupationGrid grid = OccupationGrid::fill(base.withBins(n), samples, weights);
    const Contour contour = grid.contour(options.level);
    BinningTrial trial;
    trial.binsPerAxis = n;
    trial.occupiedBins = grid.occupiedBins();
    trial.selectedBins = contour.selectedBins;
    trial.selectedProbability = contour.probability;
    trial.connectivity = analyseConnectivity(grid.binning(), grid.selectedIndices(contour));
    if (trial.connectivity.connected) result.finestConnected = n;
    result.trials.push_back(trial);
  }
  return result;
}

}  // namespace octarc
