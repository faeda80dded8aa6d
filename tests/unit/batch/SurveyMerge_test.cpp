#include "octarc/batch/SurveyMerge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "ExpectError.h"
#include "FitsHeaders.h"
#include "octarc/selection/SearchMask.h"

namespace octarc {
namespace {

constexpr int kWidth = 200, kHeight = 100;
constexpr double kScaleDeg = 1.0 / 3600.0;  // 1 arcsec per pixel

// A TAN WCS at (150, 2) whose reference pixel is at x = crpix1: tile B, with crpix1 150 pixels
// lower, shows at its pixel x the sky of tile A's pixel x + 150.
Wcs tanWcs(double crpix1) {
  const FitsHeader h = test::imageHeader(kWidth, kHeight,
                                         {{"CTYPE1", "'RA---TAN'"},
                                          {"CTYPE2", "'DEC--TAN'"},
                                          {"CRPIX1", std::to_string(crpix1)},
                                          {"CRPIX2", "50.5"},
                                          {"CRVAL1", "150.0"},
                                          {"CRVAL2", "2.0"},
                                          {"CD1_1", "-2.777777777777778E-04"},
                                          {"CD2_2", "2.777777777777778E-04"},
                                          {"RADESYS", "'ICRS'"}});
  return *Wcs::fromHeader(h, "tile.fits");
}

struct Row {
  double x, y, prob;
  int spaces;
};

// A tile of candidates at 1-based pixel positions, its whole area searched.
TileCandidates tile(const std::string& name, double crpix1, const std::vector<Row>& rows) {
  TileCandidates t;
  t.name = name;
  t.wcs = tanWcs(crpix1);
  t.widthPix = kWidth;
  t.heightPix = kHeight;
  t.blockPix = SearchMask::kAreaBlockPix;
  t.searchedBlocks = SearchMask(kWidth, kHeight, {}).blockCounts();
  t.pixelScaleArcsec = 1.0;
  std::vector<std::int32_t> number, spaces;
  std::vector<std::string> names;
  std::vector<double> ra, dec, prob;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto sky = t.wcs->pixelToJ2000(rows[i].x, rows[i].y);
    number.push_back(std::int32_t(i + 1));
    names.push_back(name + "-" + std::to_string(i + 1));
    ra.push_back(sky[0]);
    dec.push_back(sky[1]);
    prob.push_back(rows[i].prob);
    spaces.push_back(rows[i].spaces);
  }
  t.candidates.name = "LDAC_OBJECTS";
  t.candidates.columns = {
      {"NUMBER", "", "", "", 1, number, "", ""},     {"NAME", "", "", "", 0, names, "", ""},
      {"ALPHA_J2000", "", "deg", "", 1, ra, "", ""}, {"DELTA_J2000", "", "deg", "", 1, dec, "", ""},
      {"LENS_SCORE", "", "", "", 1, prob, "", ""},   {"LENS_RANK", "", "", "", 1, number, "", ""},
      {"SPACES", "", "", "", 1, spaces, "", ""}};
  t.candidates.keywords = {FitsKeyword::integer("NSPACES", 1), FitsKeyword::text("SPNAME1", "A015"),
                           FitsKeyword::text("SPEXPR1", "ARCNESS > 0.15")};
  return t;
}

TEST(SurveyMerge, OverlapCopiesKeptOnceAndTheUnionArea) {
  // A#1 at (180, 50) and B#1 at (30.2, 50), i.e. A's (180.2, 50): 0.2" apart, one object. A#1
  // is 79.5 px from A's centre (100.5, 50.5), B#1 70.3 px from B's: B's copy is kept. A#2 and
  // A#3 are 0.1" apart in the same tile: two candidates. C lies beyond B, 50" from it.
  const std::vector<TileCandidates> tiles = {
      tile("A", 100.5, {{180.0, 50.0, 0.9, 1}, {20.0, 50.0, 0.5, 0}, {20.1, 50.0, 0.4, 1}}),
      tile("B", 100.5 - 150.0, {{30.2, 50.0, 0.9, 1}, {100.0, 50.0, 0.1, 0}}),
      tile("C", 100.5 - 400.0, {{50.0, 50.0, 0.7, 1}})};
  const SurveyCandidates merged = mergeTiles(tiles, 1.0);
  EXPECT_EQ(merged.tileCandidates, 6);
  EXPECT_EQ(merged.duplicatesRemoved, 1);
  ASSERT_EQ(merged.table.rows(), 5);
  // By LENS_SCORE: B#1 (0.9), C#1 (0.7), A#2 (0.5), A#3 (0.4), B#2 (0.1).
  EXPECT_EQ(merged.table.strings("TILE"), (std::vector<std::string>{"B", "C", "A", "A", "B"}));
  EXPECT_EQ(merged.table.integers("TILE_NUMBER"), (std::vector<std::int64_t>{1, 1, 2, 3, 2}));
  EXPECT_EQ(merged.table.integers("NUMBER"), (std::vector<std::int64_t>{1, 2, 3, 4, 5}));
  // The rank is the survey's, not the tile's (A#3 was 3rd in its tile).
  EXPECT_EQ(merged.table.integers("LENS_RANK"), (std::vector<std::int64_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(merged.table.strings("NAME")[0], "B-1");
  EXPECT_EQ(merged.keptPerTile, (std::vector<std::int64_t>{2, 2, 1}));
  ASSERT_EQ(merged.spaces.size(), 1u);
  EXPECT_EQ(merged.spaces[0].name, "A015");
  EXPECT_EQ(merged.spaces[0].candidates, 3);  // B#1, C#1, A#3

  // The union: A and B share 50 of their 200 columns, C stands alone: (350 + 200) x 100 pixels
  // of 1 arcsec^2 (TAN within 10 arcmin of its tangent point: within 1e-5). The overlap's edge
  // crosses a column of B's blocks, followed to the pixel.
  const double pixelDeg2 = kScaleDeg * kScaleDeg;
  const double exact = 550.0 * 100.0 * pixelDeg2;
  EXPECT_NEAR(merged.areaDeg2, exact, 1e-5 * exact);
  EXPECT_LT(merged.areaDeg2, 600.0 * 100.0 * pixelDeg2 * 0.95);  // not the plain sum
}

TEST(SurveyMerge, TwoObjectsOfOneTileStayTwoWhenAnotherTilesCopyLiesBetween) {
  // A#1 and A#2 are 0.8" apart; B#1 is 0.4" from each. B#1 (70 px from B's centre) is kept
  // first and is A#1 seen again; A#2 is another object, though B#1 is within 1" of it too.
  const std::vector<TileCandidates> tiles = {
      tile("A", 100.5, {{180.0, 50.0, 0.5, 0}, {180.8, 50.0, 0.4, 0}}),
      tile("B", 100.5 - 150.0, {{30.4, 50.0, 0.9, 0}})};
  const SurveyCandidates merged = mergeTiles(tiles, 1.0);
  EXPECT_EQ(merged.duplicatesRemoved, 1);
  ASSERT_EQ(merged.table.rows(), 2);
  EXPECT_EQ(merged.table.strings("TILE"), (std::vector<std::string>{"B", "A"}));
  EXPECT_EQ(merged.table.integers("TILE_NUMBER"), (std::vector<std::int64_t>{1, 2}));
}

TEST(SurveyMerge, TilesWithoutWcsAreAddedAsTheyAre) {
  TileCandidates a = tile("A", 100.5, {{20.0, 50.0, 0.5, 0}});
  TileCandidates b = tile("B", 100.5, {{20.0, 50.0, 0.6, 0}});  // same sky as A#1
  a.wcs.reset();
  b.wcs.reset();
  b.pixelScaleArcsec = 2.0;
  const SurveyCandidates merged = mergeTiles({a, b}, 1.0);
  EXPECT_EQ(merged.table.rows(), 2);
  EXPECT_EQ(merged.duplicatesRemoved, 0);
  const double pixelDeg2 = kScaleDeg * kScaleDeg;
  EXPECT_NEAR(merged.areaDeg2, 20000.0 * pixelDeg2 * (1.0 + 4.0), 1e-12);
}

TEST(SurveyMerge, TablesOfOtherColumnsAreRefused) {
  TileCandidates a = tile("A", 100.5, {});
  TileCandidates b = tile("B", 100.5, {});
  b.candidates.columns.pop_back();
  test::expectError<ConfigError>(
      [&] {
        mergeTiles({a, b}, 1.0);
      },
      {"tile B", "other columns", "tile A"});
}

// NSPACES counts the bits of SPACES: 0 to 30 spaces are read, more are refused naming the
// tile's file and the card.
TEST(SurveyMerge, ReportSpaceCountsOutOfTheirRangeAreRefused) {
  const auto withSpaces = [](std::int64_t count) {
    TileCandidates t = tile("A", 100.5, {{20.0, 50.0, 0.5, 1}});
    t.candidates.source = "tiles/A/candidates.fits";
    t.candidates.keywords = {FitsKeyword::integer("NSPACES", count)};
    for (std::int64_t s = 1; s <= std::max<std::int64_t>(count, 31); ++s) {
      t.candidates.keywords.push_back(FitsKeyword::text("SPNAME" + std::to_string(s), "S"));
      t.candidates.keywords.push_back(FitsKeyword::text("SPEXPR" + std::to_string(s), "X > 0"));
    }
    return t;
  };
  EXPECT_TRUE(mergeTiles({withSpaces(0)}, 1.0).spaces.empty());
  const SurveyCandidates thirty = mergeTiles({withSpaces(30)}, 1.0);
  ASSERT_EQ(thirty.spaces.size(), 30u);
  EXPECT_EQ(thirty.spaces[0].candidates, 1);  // bit 0 of the one candidate's SPACES
  EXPECT_EQ(thirty.spaces[29].candidates, 0);
  for (const std::int64_t count : {std::int64_t(31), std::int64_t(-1)}) {
    test::expectIoError([&] { mergeTiles({withSpaces(count)}, 1.0); },
                        {"tiles/A/candidates.fits[LDAC_OBJECTS]: NSPACES = " +
                         std::to_string(count) + " is not an integer from 0 to 30"});
  }
}

}  // namespace
}  // namespace octarc
