// Connectivity of selected bins on constructed grids.
#include "octarc/selection/Connectivity.h"

#include <gtest/gtest.h>

#include <vector>

namespace octarc {
namespace {

GridBinning grid(std::vector<int> bins) {
  std::vector<GridAxis> axes;
  for (int n : bins) axes.push_back(GridAxis{"X", 0.0, 1.0, n});
  return GridBinning(axes);
}

// Packed indices of 2-D bins (x, y).
std::vector<BinIndex> bins2d(const GridBinning& b, const std::vector<std::vector<int>>& xy) {
  std::vector<BinIndex> out;
  for (const std::vector<int>& k : xy) out.push_back(b.pack(k));
  return out;
}

TEST(Connectivity, FaceNeighboursAreConnected) {
  const GridBinning b = grid({4, 4});
  const Connectivity c = analyseConnectivity(b, bins2d(b, {{1, 1}, {2, 1}, {2, 2}, {2, 3}}));
  EXPECT_TRUE(c.connected);
  EXPECT_EQ(c.isolatedBins, 0);
  EXPECT_EQ(c.components, 1);
}

TEST(Connectivity, AnIsolatedBinIsRejected) {
  const GridBinning b = grid({4, 4});
  const Connectivity c = analyseConnectivity(b, bins2d(b, {{0, 0}, {1, 0}, {3, 3}}));
  EXPECT_FALSE(c.connected);
  EXPECT_EQ(c.isolatedBins, 1);
  EXPECT_EQ(c.components, 2);
}

TEST(Connectivity, ADiagonalNeighbourDoesNotCount) {
  const GridBinning b = grid({4, 4});
  const Connectivity c = analyseConnectivity(b, bins2d(b, {{1, 1}, {2, 2}}));
  EXPECT_FALSE(c.connected);
  EXPECT_EQ(c.isolatedBins, 2);
  EXPECT_EQ(c.components, 2);
  // The same pair joined through a face neighbour of both.
  EXPECT_TRUE(analyseConnectivity(b, bins2d(b, {{1, 1}, {2, 2}, {2, 1}})).connected);
}

TEST(Connectivity, TwoComponentsEachConnectedPass) {
  // Every bin touches another, though the two groups never touch: METHOD's condition holds.
  const GridBinning b = grid({4, 4});
  const Connectivity c = analyseConnectivity(b, bins2d(b, {{0, 0}, {0, 1}, {3, 2}, {3, 3}}));
  EXPECT_TRUE(c.connected);
  EXPECT_EQ(c.isolatedBins, 0);
  EXPECT_EQ(c.components, 2);
}

TEST(Connectivity, NoWrapAroundAndNoPackedIndexShortcut) {
  // 1-D: bins 0 and 4 of 5 are the two ends, not neighbours.
  const GridBinning line = grid({5});
  EXPECT_FALSE(analyseConnectivity(line, {0, 4}).connected);
  EXPECT_TRUE(analyseConnectivity(line, {3, 4}).connected);
  // 2-D 3 x 3: (2, 0) and (0, 1) have consecutive packed indices, 2 and 3, but do not touch.
  const GridBinning b = grid({3, 3});
  const std::vector<BinIndex> pair = bins2d(b, {{2, 0}, {0, 1}});
  EXPECT_EQ(pair, (std::vector<BinIndex>{2, 3}));
  EXPECT_FALSE(analyseConnectivity(b, pair).connected);
}

TEST(Connectivity, LoneAndEmptySelections) {
  const GridBinning b = grid({3, 3});
  const Connectivity lone = analyseConnectivity(b, {4});
  EXPECT_FALSE(lone.connected);  // a single bin touches no other
  EXPECT_EQ(lone.isolatedBins, 1);
  EXPECT_EQ(lone.components, 1);
  const Connectivity none = analyseConnectivity(b, {});
  EXPECT_FALSE(none.connected);
  EXPECT_EQ(none.components, 0);
}

TEST(Connectivity, ThreeAndSixDimensions) {
  // An L through the third axis: (0,0,0) - (0,0,1) - (1,0,1).
  const GridBinning b3 = grid({2, 2, 2});
  const std::vector<int> a = {0, 0, 0}, m = {0, 0, 1}, e = {1, 0, 1}, d = {1, 1, 0};
  const Connectivity l = analyseConnectivity(b3, {b3.pack(a), b3.pack(m), b3.pack(e)});
  EXPECT_TRUE(l.connected);
  EXPECT_EQ(l.components, 1);
  // (1,1,0) touches (0,0,0)... only diagonally, and (1,0,1) only diagonally too.
  const Connectivity split = analyseConnectivity(b3, {b3.pack(a), b3.pack(m), b3.pack(d)});
  EXPECT_FALSE(split.connected);
  EXPECT_EQ(split.isolatedBins, 1);
  EXPECT_EQ(split.components, 2);
  // 6-D, 10 bins per axis: two bins differing by 1 along the last axis touch; by 1 along two
  // axes they do not.
  const GridBinning b6 = grid({10, 10, 10, 10, 10, 10});
  const std::vector<int> p = {3, 4, 5, 6, 7, 8}, q = {3, 4, 5, 6, 7, 9}, r = {3, 4, 5, 6, 8, 9};
  EXPECT_TRUE(analyseConnectivity(b6, {b6.pack(p), b6.pack(q)}).connected);
  EXPECT_FALSE(analyseConnectivity(b6, {b6.pack(p), b6.pack(r)}).connected);
}

}  // namespace
}  // namespace octarc
