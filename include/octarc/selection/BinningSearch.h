// The binning of the occupation grid (METHOD.md section 4): bins as small as possible, to reject
// the most spurious objects, as long as the bins of the contour at level P stay connected
// (selection/Connectivity.h).
//
// The search takes the axes' ranges as fixed (given, or from quantileRange() of the filled
// values) and tries the same number of bins n on every axis, for every n from minBins to
// maxBins, coarse to fine, and keeps the largest n that passes. Connectivity is not monotonic
// in n: refining moves every bin edge, so a sparse group of samples that falls into two
// adjacent bins at one n can fall into one lone bin at n + 1 and into two adjacent ones again
// at a larger n (BinningSearch tests build such a set). Stopping at the first n that fails
// would then miss finer binnings that pass, so the whole range is searched; every n tried is
// reported, so that the choice can be checked.
#pragma once

#include <cstdint>
#include <vector>

#include "octarc/selection/Connectivity.h"
#include "octarc/selection/GridBinning.h"

namespace octarc {

struct BinningSearchOptions {
  double level = 0.99;  // contour level P
  int minBins = 2;      // one bin per axis is one lone bin: never connected
  int maxBins = 50;
};

// What one binning gave.
struct BinningTrial {
  int binsPerAxis = 0;
  std::int64_t occupiedBins = 0;
  std::int64_t selectedBins = 0;     // by the contour at the level
  double selectedProbability = 0.0;  // what they hold
  Connectivity connectivity;
};

struct BinningSearchResult {
  BinningSearchOptions options;      // what was searched
  int finestConnected = 0;           // the largest n that passed; 0 when none did
  std::vector<BinningTrial> trials;  // every n tried, coarse to fine

  // finestConnected, or ConfigError when no n passed (with the range and the level).
  int requireFinest() const;
};

// Tries every n of the options on the axes (their ranges; their bin counts are ignored) filled
// with `samples` and their `weights` (OccupationGrid::fill; empty: 1 each). Throws ConfigError for
// a bin range that is empty or below 1, and whatever OccupationGrid::fill and contour() throw (no
// sample in the grid).
BinningSearchResult findFinestConnectedBinning(const std::vector<GridAxis>& axes,
                                               const AxisSamples& samples,
                                               const BinningSearchOptions& options,
                                               const std::vector<double>& weights = {});

}  // namespace octarc
