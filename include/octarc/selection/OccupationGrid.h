// The occupation-probability grid of simulated arcs (METHOD.md section 4): every simulated
// system adds its arc (the row of its randomly chosen threshold level) to the bin its axis
// values fall in, with its weight (SIM_WEIGHT: how many systems of the population the row
// stands for; 1 when not given); normalised, each bin holds the probability that an arc of the
// population falls in it.
//
// Conventions (bins and packed indices: selection/GridBinning.h)
//   Normalisation: probability = weight / binned weight, the weight of a bin the sum of the
//   weights of its samples and the binned weight that of the samples that fell in a bin. The
//   samples' count is kept beside it (count, binnedCount()): with unit weights weight = count.
//   Samples with an axis value outside its range (outsideCount()) or NaN (undefinedCount(),
//   e.g. a system without an arc) are counted but in no bin, so the probabilities of the
//   occupied bins sum to 1 and a contour at level P holds at least a fraction P of the binned
//   weight. A sample of weight 0 (or not finite) is counted as undefined: it stands for nothing.
//   Order: occupied bins sorted by probability, highest first; equal probabilities (equal
//   weights) by packed index, lowest first, so the order never depends on filling order.
//   cumulative(bin) = the sum of the probabilities of that bin and of every bin before it in
//   that order, computed as (sum of weights) / binned weight: exact for sums that are exact in
//   binary (whole numbers: unit weights).
//   It is the "contour level at which the bin enters": the contour at P = cumulative(bin) is
//   that bin and every bin before it; every contour of a higher level holds the bin, and no
//   contour of a level at or below the cumulative of the bin before it does.
//   Contour at level P, 0 < P <= 1: the smallest set of most probable bins whose probabilities
//   sum to at least P, i.e. the first k bins of the order with k the first rank whose cumulative
//   is >= P. When probabilities tie at the boundary, the tie order decides which bin is in.
//
// Storage is sparse: a hash map from packed index to rank, and the sorted bins, so that memory
// grows with the occupied bins, never with the total number of bins (a 6-D grid of 100 bins
// per axis has 10^12 bins; 10^5 samples occupy at most 10^5 of them). An occupied bin costs
// about 90 bytes with glibc and libstdc++: a hash node (key, rank and next pointer, 24 bytes, 32
// as allocated), 8-16 bytes of bucket array at the map's load factor, and a 40-byte GridBin.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/selection/GridBinning.h"

namespace octarc {

struct GridBin {
  BinIndex index = 0;
  std::int64_t count = 0;    // samples in the bin
  double weight = 0.0;       // their weight sum (= count with unit weights)
  double probability = 0.0;  // weight / binned weight
  double cumulative = 0.0;   // contour level at which the bin enters (see above)
};

// The contour at one level: the first selectedBins of OccupationGrid::bins().
struct Contour {
  double level = 0.0;  // P asked for
  std::int64_t selectedBins = 0;
  double probability = 0.0;  // what the selected bins hold, >= level
  bool selects(std::int64_t rank) const { return rank >= 0 && rank < selectedBins; }
};

class OccupationGrid {
 public:
  // Fills a grid with samples (one per simulated system): samples[a][i] is axis a of sample i,
  // weights[i] its weight (empty: 1 each). Throws ConfigError when the number of axes of
  // `samples` is not the binning's or the axes (or the weights) hold different numbers of
  // samples.
  static OccupationGrid fill(GridBinning binning, const AxisSamples& samples,
                             const std::vector<double>& weights = {});
  // A grid from its occupied bins and counts (as stored in a grid file). Throws ConfigError for
  // a bin index outside the grid, a bin given twice or a count below 1.
  static OccupationGrid fromCounts(GridBinning binning,
                                   const std::vector<std::pair<BinIndex, std::int64_t>>& counts,
                                   std::int64_t outside, std::int64_t undefined);
  // A grid from its occupied bins, counts and weights (index, count and weight of each GridBin;
  // its probability and cumulative are recomputed). ConfigError as fromCounts, and for a weight
  // that is not finite and positive.
  static OccupationGrid fromWeights(GridBinning binning, const std::vector<GridBin>& bins,
                                    std::int64_t outside, std::int64_t undefined);

  const GridBinning& binning() const { return binning_; }
  std::int64_t binnedCount() const { return binned_; }
  double binnedWeight() const { return binnedWeight_; }
  std::int64_t outsideCount() const { return outside_; }
  std::int64_t undefinedCount() const { return undefined_; }
  std::int64_t occupiedBins() const { return std::int64_t(bins_.size()); }

  // Occupied bins in probability order (see above).
  const std::vector<GridBin>& bins() const { return bins_; }
  // Rank of a bin in bins(), or -1 for an empty bin.
  std::int64_t rankOf(BinIndex index) const;
  // The bin a sample (one value per axis) falls in: its packed index, or nullopt (outside the
  // grid or NaN). ConfigError for a sample of another number of axes.
  std::optional<BinIndex> binOf(std::span<const double> values) const;

  // The contour at level P. Throws ConfigError for P outside (0, 1], and for a grid with no
  // occupied bin ("the contour at P = ... selects nothing", with the counts outside and
  // undefined).
  Contour contour(double level) const;
  // Packed indices of the bins the contour selects, in probability order.
  std::vector<BinIndex> selectedIndices(const Contour& contour) const;

 private:
  // `bins` (index, count, weight) and `rank`, a map holding every bin's index (its values are
  // overwritten with the ranks).
  OccupationGrid(GridBinning binning, std::vector<GridBin> bins,
                 std::unordered_map<BinIndex, std::int64_t> rank, std::int64_t outside,
                 std::int64_t undefined);

  GridBinning binning_;
  std::int64_t binned_ = 0;
  double binnedWeight_ = 0.0;
  std::int64_t outside_ = 0;
  std::int64_t undefined_ = 0;
  std::vector<GridBin> bins_;
  std::unordered_map<BinIndex, std::int64_t> rank_;
};

// The axis values of the rows of `table` kept by `mask` (every row when `mask` is empty), for
// OccupationGrid::fill and the scoring: samples[a] holds expression a's values. Throws
// ConfigError for an expression that does not parse or names an unknown column, naming the
// axis.
AxisSamples evaluateAxes(const std::vector<std::string>& expressions, const Table& table,
                         const std::vector<bool>& mask = {});

}  // namespace octarc
