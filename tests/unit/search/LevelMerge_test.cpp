#include "octarc/search/LevelMerge.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "ExpectError.h"

namespace octarc {
namespace {

// A constructed component tree (level, NUMBER, PARENT_NUMBER), with selection and score:
//
//   level 1   A (1) -            B (2) 0.2
//   level 2   A1 (1) 0.5   A2 (2) 0.7         B1 (3) -
//   level 3   A1a (1) 0.9  A2a (2) -          B1a (3) 0.4
//   level 4                A2aa (1) 0.7
//
// ("-": not selected). A did not pass, so its children A1 and A2 are separate objects; A2aa
// reaches A2 across the unselected A2a, B1a reaches B across B1.
struct Tree {
  std::vector<TreeRow> rows = {
      {1, 1, 0},  // 0 A
      {1, 2, 0},  // 1 B
      {2, 1, 1},  // 2 A1
      {2, 2, 1},  // 3 A2
      {2, 3, 2},  // 4 B1
      {3, 1, 1},  // 5 A1a
      {3, 2, 2},  // 6 A2a
      {3, 3, 3},  // 7 B1a
      {4, 1, 2},  // 8 A2aa
  };
  std::vector<bool> passed = {false, true, true, true, false, true, false, true, true};
  std::vector<double> score = {0.1, 0.2, 0.5, 0.7, 0.3, 0.9, 0.6, 0.4, 0.7};
};

TEST(LevelMerge, ConstructedTreeGivesOneObjectPerBranch) {
  const Tree t;
  const auto objects = mergeAcrossLevels(t.rows, t.passed, t.score);
  ASSERT_EQ(objects.size(), 3U);
  // A1 + A1a: best A1a (0.9).
  EXPECT_EQ(objects[0].bestRow, 5U);
  EXPECT_EQ(objects[0].rows, (std::vector<std::size_t>{2, 5}));
  EXPECT_EQ(objects[0].passedLevels, (std::vector<int>{2, 3}));
  // A2 + A2aa: equal scores, the lower level wins.
  EXPECT_EQ(objects[1].bestRow, 3U);
  EXPECT_EQ(objects[1].rows, (std::vector<std::size_t>{3, 8}));
  EXPECT_EQ(objects[1].passedLevels, (std::vector<int>{2, 4}));
  // B + B1a: best B1a (0.4).
  EXPECT_EQ(objects[2].bestRow, 7U);
  EXPECT_EQ(objects[2].rows, (std::vector<std::size_t>{1, 7}));
  EXPECT_EQ(objects[2].passedLevels, (std::vector<int>{1, 3}));
}

TEST(LevelMerge, ASelectedParentJoinsItsSelectedChildren) {
  Tree t;
  t.passed[0] = true;  // A passes: A1 and A2 both reach it
  const auto objects = mergeAcrossLevels(t.rows, t.passed, t.score);
  ASSERT_EQ(objects.size(), 2U);
  EXPECT_EQ(objects[0].bestRow, 5U);
  EXPECT_EQ(objects[0].rows, (std::vector<std::size_t>{0, 2, 3, 5, 8}));
  EXPECT_EQ(objects[0].passedLevels, (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(objects[1].rows, (std::vector<std::size_t>{1, 7}));
}

TEST(LevelMerge, AMissingParentEndsTheWalk) {
  // Level 2 of a filtered catalog lacks object 7: its level-3 child stands alone.
  const std::vector<TreeRow> rows = {{1, 1, 0}, {3, 1, 7}, {2, 1, 1}};
  const auto objects = mergeAcrossLevels(rows, {true, true, true}, {0.5, 0.6, 0.1});
  ASSERT_EQ(objects.size(), 2U);
  EXPECT_EQ(objects[0].rows, (std::vector<std::size_t>{1}));
  EXPECT_EQ(objects[1].rows, (std::vector<std::size_t>{0, 2}));
  EXPECT_TRUE(mergeAcrossLevels(rows, {false, false, false}, {0, 0, 0}).empty());
}

// A row that could not be scored (NaN) never becomes the best row of an object that has a
// scored one, and objects with only NaN scores come last.
TEST(LevelMerge, NanScoresRankLast) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<TreeRow> rows = {{1, 1, 0}, {2, 1, 1}, {1, 2, 0}, {1, 3, 0}};
  const auto objects = mergeAcrossLevels(rows, {true, true, true, true}, {nan, 0.3, nan, 0.1});
  ASSERT_EQ(objects.size(), 3U);
  EXPECT_EQ(objects[0].bestRow, 1U);
  EXPECT_EQ(objects[0].rows, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(objects[1].bestRow, 3U);
  EXPECT_EQ(objects[2].bestRow, 2U);
}

TEST(LevelMerge, InconsistentInputIsAConfigError) {
  test::expectError<ConfigError>(
      [] {
        mergeAcrossLevels({{1, 1, 0}, {1, 1, 0}}, {true, true}, {1, 1});
      },
      {"object 1 of level 1"});
  test::expectError<ConfigError>(
      [] {
        mergeAcrossLevels({{1, 1, 0}}, {true, true}, {1});
      },
      {"1 rows", "2 selection flags"});
}

}  // namespace
}  // namespace octarc
