// Scoring catalog rows against a hand-made grid.
#include "octarc/selection/GridScore.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "SelectionTestSupport.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

// Axes X over [0, 3) in 3 bins and log10(S) over [0, 2) in 2 bins: 6 bins, packed x + 3 y.
// Filled with 4 samples in (0, 0) = packed 0, 2 in (1, 0) = 1, 1 in (0, 1) = 3, 1 in
// (1, 1) = 4; bins 2 and 5 stay empty. Probabilities 0.5, 0.25, 0.125, 0.125 (the tie to the
// lower index, 3), cumulative 0.5, 0.75, 0.875, 1. The contour at 0.75 is bins 0 and 1.
OccupationGrid handMadeGrid() {
  const GridBinning b({GridAxis{"X", 0.0, 3.0, 3}, GridAxis{"log10(S)", 0.0, 2.0, 2}});
  return OccupationGrid::fill(
      b, {{0.5, 0.5, 0.5, 0.5, 1.5, 1.5, 0.5, 1.5}, {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 1.5, 1.5}});
}

TEST(GridScore, RowsScoreTheirBinsProbabilityAndEntryLevel) {
  const OccupationGrid grid = handMadeGrid();
  const Contour contour = grid.contour(0.75);
  ASSERT_EQ(contour.selectedBins, 2);
  // S = 10^y: log10 of 1, 10 and 100 is exactly 0, 1 and 2.
  const Table catalog = test::makeTable({
      {"X", {0.2, 1.9, 0.0, 2.5, 3.0, kNaN, 1.0, 0.5}},
      {"S", {1.0, 3.0, 10.0, 3.0, 3.0, 3.0, 99.0, 100.0}},
  });
  const std::vector<RowScore> s = scoreRows(grid, contour, catalog);
  ASSERT_EQ(s.size(), 8u);
  // Row 0: (0.2, 0) -> bin 0, the most probable, in the contour.
  EXPECT_EQ(s[0].status, ScoreStatus::OccupiedBin);
  EXPECT_EQ(s[0].probability, 0.5);
  EXPECT_EQ(s[0].entryLevel, 0.5);
  EXPECT_EQ(s[0].rank, 0);
  EXPECT_TRUE(s[0].selected);
  // Row 1: (1.9, 0.477) -> bin 1.
  EXPECT_EQ(s[1].probability, 0.25);
  EXPECT_EQ(s[1].entryLevel, 0.75);
  EXPECT_TRUE(s[1].selected);
  // Row 2: (0, 1) -> bin (0, 1) = 3, occupied but outside the contour.
  EXPECT_EQ(s[2].status, ScoreStatus::OccupiedBin);
  EXPECT_EQ(s[2].probability, 0.125);
  EXPECT_EQ(s[2].entryLevel, 0.875);
  EXPECT_EQ(s[2].rank, 2);
  EXPECT_FALSE(s[2].selected);
  // Row 3: (2.5, 0.477) -> bin 2, which no simulated arc occupies: score 0.
  EXPECT_EQ(s[3].status, ScoreStatus::EmptyBin);
  EXPECT_EQ(s[3].probability, 0.0);
  EXPECT_TRUE(std::isnan(s[3].entryLevel));
  EXPECT_EQ(s[3].rank, -1);
  EXPECT_FALSE(s[3].selected);
  // Row 4: x = 3 is the excluded upper edge; row 5: x NaN.
  EXPECT_EQ(s[4].status, ScoreStatus::Outside);
  EXPECT_EQ(s[4].probability, 0.0);
  EXPECT_FALSE(s[4].selected);
  EXPECT_EQ(s[5].status, ScoreStatus::Undefined);
  EXPECT_FALSE(s[5].selected);
  // Row 6: (1, 1.996) -> bin (1, 1) = 4, last in the order: entry level 1.
  EXPECT_EQ(s[6].probability, 0.125);
  EXPECT_EQ(s[6].entryLevel, 1.0);
  EXPECT_EQ(s[6].rank, 3);
  // Row 7: log10(100) = 2 is the excluded upper edge of the second axis.
  EXPECT_EQ(s[7].status, ScoreStatus::Outside);

  // A wider contour takes rows 2 and 6 in.
  const std::vector<RowScore> all = scoreRows(grid, grid.contour(1.0), catalog);
  EXPECT_TRUE(all[2].selected);
  EXPECT_TRUE(all[6].selected);
  EXPECT_FALSE(all[3].selected);
}

TEST(GridScore, CatalogWithoutAnAxisColumn) {
  const OccupationGrid grid = handMadeGrid();
  const Table catalog = test::makeTable({{"X", {0.5}}, {"SNR", {3.0}}});
  test::expectError<ConfigError>(
      [&] { scoreRows(grid, grid.contour(0.5), catalog); },
      {"grid axis 2 (log10(S))", "unknown column S", "(columns: X, SNR)"});
  test::expectError<ConfigError>([&] { scoreSamples(grid, grid.contour(0.5), {{0.5}}); },
                                 {"grid of 2 axes with 1 axes"});
}

}  // namespace
}  // namespace octarc
