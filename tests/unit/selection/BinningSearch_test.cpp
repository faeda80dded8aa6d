// The binning search on point sets whose finest connected binning is known by construction.
#include "octarc/selection/BinningSearch.h"

#include <gtest/gtest.h>

#include <vector>

#include "SelectionTestSupport.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

// On [0, 1): a dense block of 300 samples at (i + 0.5) / 1000, i = 0..299 (0.0005 to 0.2995),
// and a lone pair at 0.59 and 0.61. With n bins of width 1/n, the block fills bins 0 to
// L = floor(0.2995 n) (its spacing, 0.001, is far below 1/n), and the pair falls in
// floor(0.59 n) and floor(0.61 n). At P = 1 every occupied bin is selected; the set is
// connected when the pair's bins touch each other or the block:
//   n   L   pair bins  connected
//   2   0   1, 1       yes (1 touches the block)
//   3   0   1, 1       yes
//   4   1   2, 2       yes
//   5   1   2, 3       yes
//   6   1   3, 3       no  (bin 3 alone)
//   7   2   4, 4       no
//   8   2   4, 4       no
//   9   2   5, 5       no
//  10   2   5, 6       yes (two adjacent bins, a second component)
//  11   3   6, 6       no
//  12   3   7, 7       no
// So the finest connected binning up to 12 is 10, and a search stopping at its first failure
// would have answered 5.
std::vector<double> blockAndPair() {
  std::vector<double> x;
  for (int i = 0; i < 300; ++i) x.push_back((i + 0.5) / 1000.0);
  x.push_back(0.59);
  x.push_back(0.61);
  return x;
}

TEST(BinningSearch, FindsTheFinestConnectedBinningBeyondAFailure) {
  const std::vector<GridAxis> axes = {{"X", 0.0, 1.0, 1}};
  const BinningSearchResult r = findFinestConnectedBinning(axes, {blockAndPair()}, {1.0, 2, 12});
  EXPECT_EQ(r.finestConnected, 10);
  EXPECT_EQ(r.requireFinest(), 10);
  ASSERT_EQ(r.trials.size(), 11u);
  const std::vector<bool> connected = {true,  true,  true, true,  false, false,
                                       false, false, true, false, false};
  const std::vector<std::int64_t> occupied = {2, 2, 3, 4, 3, 4, 4, 4, 5, 5, 5};
  for (std::size_t i = 0; i < r.trials.size(); ++i) {
    const BinningTrial& t = r.trials[i];
    EXPECT_EQ(t.binsPerAxis, int(i) + 2);
    EXPECT_EQ(t.connectivity.connected, connected[i]) << "n = " << t.binsPerAxis;
    EXPECT_EQ(t.occupiedBins, occupied[i]) << "n = " << t.binsPerAxis;
    EXPECT_EQ(t.selectedBins, t.occupiedBins);  // P = 1 takes every occupied bin
    EXPECT_EQ(t.selectedProbability, 1.0);
  }
  EXPECT_EQ(r.trials[4].connectivity.isolatedBins, 1);  // n = 6: the pair's lone bin
  EXPECT_EQ(r.trials[8].connectivity.components, 2);    // n = 10: block and pair
}

TEST(BinningSearch, ALowerLevelLeavesThePairOut) {
  // At P = 0.99 the contour needs 0.99 * 302 = 298.98 samples: the block's 300, never the pair's
  // bins (at most 2 samples each, fewer than any block bin). From n = 4 on the block spans at
  // least two bins and is connected; at n = 2 and 3 it is one lone bin.
  const std::vector<GridAxis> axes = {{"X", 0.0, 1.0, 1}};
  const BinningSearchResult r = findFinestConnectedBinning(axes, {blockAndPair()}, {0.99, 2, 12});
  EXPECT_EQ(r.finestConnected, 12);
  EXPECT_FALSE(r.trials[0].connectivity.connected);
  EXPECT_EQ(r.trials[0].selectedBins, 1);
  EXPECT_FALSE(r.trials[1].connectivity.connected);
  for (std::size_t i = 2; i < r.trials.size(); ++i) {
    EXPECT_TRUE(r.trials[i].connectivity.connected) << "n = " << r.trials[i].binsPerAxis;
    EXPECT_EQ(r.trials[i].selectedProbability, 300.0 / 302.0);
  }
}

TEST(BinningSearch, TheSameStructureInTwoDimensions) {
  // A second axis on which every sample sits at 0.5: it adds nothing, so the answer is the
  // one-dimensional one.
  const std::vector<double> x = blockAndPair();
  const std::vector<double> y(x.size(), 0.5);
  const std::vector<GridAxis> axes = {{"X", 0.0, 1.0, 1}, {"Y", 0.0, 1.0, 1}};
  const BinningSearchResult r = findFinestConnectedBinning(axes, {x, y}, {1.0, 2, 12});
  EXPECT_EQ(r.finestConnected, 10);
  EXPECT_FALSE(r.trials[9].connectivity.connected);  // n = 11
}

TEST(BinningSearch, NoConnectedBinningIsAnErrorOnRequest) {
  // Two samples, 0.1 and 0.9: for 3 to 5 bins they sit in the first and the last bin, apart.
  const std::vector<GridAxis> axes = {{"X", 0.0, 1.0, 1}};
  const BinningSearchResult r = findFinestConnectedBinning(axes, {{0.1, 0.9}}, {1.0, 3, 5});
  EXPECT_EQ(r.finestConnected, 0);
  EXPECT_EQ(r.trials.size(), 3u);
  test::expectError<ConfigError>(
      [&] { r.requireFinest(); },
      {"no binning from 3 to 5 bins per axis keeps the contour at P = 1 connected"});
  test::expectError<ConfigError>(
      [&] {
        findFinestConnectedBinning(axes, {{0.1}}, {1.0, 5, 4});
      },
      {"from 5 to 4 is not a range"});
  // No sample inside the ranges: the contour selects nothing.
  test::expectError<ConfigError>(
      [&] {
        findFinestConnectedBinning(axes, {{1.5, 2.0}}, {0.99, 2, 4});
      },
      {"selects nothing"});
}

}  // namespace
}  // namespace octarc
