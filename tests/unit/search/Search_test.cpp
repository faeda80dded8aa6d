// searchCandidates on a hand-made catalog: every cut, the merge and the lens, with answers
// worked out by hand row by row.
#include "octarc/search/Search.h"

#include <gtest/gtest.h>

#include <cmath>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

const std::vector<std::string> kColumns = {"X_IMAGE",       "Y_IMAGE",  "THRESH_LEVEL", "NUMBER",
                                           "PARENT_NUMBER", "SNR_ISO",  "SIZE_IMAGE",   "E1_IMAGE",
                                           "E2_IMAGE",      "ARC_SIDE", "ARCNESS"};

struct RowValues {
  double x, y;
  int level, number, parent;
  double snr, sizePix, e1, e2, arcSide, arcness;
};

Table catalogOf(const std::vector<RowValues>& rows) {
  std::vector<ColumnSpec> specs;
  for (const std::string& name : kColumns) {
    ColumnSpec c;
    c.name = name;
    c.type = ColumnType::Float64;
    specs.push_back(c);
  }
  Table t(specs);
  for (const RowValues& r : rows) {
    double* p = t.appendRow();
    const double v[] = {
        r.x,  r.y,  double(r.level), double(r.number), double(r.parent), r.snr, r.sizePix,
        r.e1, r.e2, r.arcSide,       r.arcness};
    for (int c = 0; c < int(kColumns.size()); ++c) p[t.offset(c)] = v[c];
  }
  return t;
}

// A 1-D ARCNESS grid on [0, 0.3) in three bins with counts 1, 5, 4: at P = 0.9 the contour holds
// bin 1 (probability 0.5, entering at 0.5) and bin 2 (0.4, entering at 0.9).
SavedGrid arcnessGrid() {
  GridBinning binning({GridAxis{"ARCNESS", 0.0, 0.3, 3}});
  OccupationGrid grid = OccupationGrid::fromCounts(binning, {{0, 1}, {1, 5}, {2, 4}}, 0, 0);
  Contour contour = grid.contour(0.9);
  return SavedGrid{std::move(grid), contour, GridProvenance{}};
}

constexpr double kScale = 0.25;  // arcsec per pixel: resolved means SIZE_IMAGE > 2.83 px

TEST(Search, EveryCutMergeAndLensByHand) {
  // An arc seen at levels 1-3 (rows 0-2), passing at 2 and 3; its lens (row 3) 10 px away on the
  // concave side (+b of theta = 0, ARC_SIDE +1, i.e. +y); a decoy galaxy on the convex side
  // (row 4); rows that fail one cut each (5-8); an object in the masked corner (9).
  const std::vector<RowValues> rows = {
      {100, 100, 1, 1, 0, 90, 5.0, 0.5, 0, 1, 0.02},      // 0: bin 0, not selected
      {100, 100, 2, 1, 1, 80, 4.0, 0.5, 0, 1, 0.12},      // 1: bin 1 (P 0.5)
      {100, 100.5, 3, 1, 1, 60, 3.5, 0.5, 0, 1, 0.25},    // 2: bin 2 (P 0.4)
      {100, 110, 1, 2, 0, 300, 6.0, 0.1, 0, 0, 0.01},     // 3: the lens
      {100, 92, 1, 3, 0, 200, 4.0, 0.1, 0, 0, 0.01},      // 4: convex-side decoy
      {300, 300, 1, 4, 0, 30, 5.0, 0.5, 0, 1, 0.15},      // 5: S/N 30 below the floor
      {320, 300, 1, 5, 0, 90, 2.0, 0.5, 0, 1, 0.15},      // 6: unresolved (sqrt 2 * 2 * 0.25 < 1)
      {340, 300, 1, 6, 0, 90, 5.0, 0.5, 0, 1, 0.31},      // 7: ARCNESS outside the grid
      {360, 300, 1, 7, 0, 90, 5.0, 0.5, 0, 1, NAN},       // 8: ARCNESS undefined
      {10, 10, 1, 8, 0, 90, 5.0, 0.5, 0, 1, 0.15},        // 9: masked
      {300, 100, 1, 9, 0, 90, 5.0, 0.0, 0.5, -1, 0.05},   // 10: bin 0, outside the contour
      {320, 100, 1, 10, 0, 45, 4.0, 0.0, 0.5, -1, 0.29},  // 11: passes alone, P 0.4
  };
  const Table catalog = catalogOf(rows);
  const SavedGrid grid = arcnessGrid();
  RegionShape corner;
  corner.kind = RegionShapeKind::Box;
  corner.exclude = true;
  corner.xCentre = 20;
  corner.yCentre = 20;
  corner.semiAxis1Pix = corner.semiAxis2Pix = 20;
  SearchMaskSettings maskSettings;
  maskSettings.regions = {corner};
  const SearchMask mask(400, 400, maskSettings);
  SearchSettings s;
  s.pixelScaleArcsec = kScale;
  s.snrMin = 40;
  s.resolvedMinArcsec = 1.0;
  s.lensRadiusArcsec = 5.0;  // 20 px
  s.reportSpaces = {SearchSpace("strong", "ARCNESS > 0.2"), SearchSpace("any", "ARCNESS > 0")};
  SearchInput in;
  in.catalog = &catalog;
  in.grid = &grid;
  in.mask = &mask;
  const SearchResult r = searchCandidates(in, s);

  // Selected rows: 1, 2 (the arc) and 11. Row 10 lies in bin 0, outside the contour.
  EXPECT_EQ(r.summary.rowsSearched, 11);  // all but the masked row
  EXPECT_EQ(r.summary.objectsSearched, 9);
  EXPECT_EQ(r.summary.rowsSelected, 3);
  EXPECT_EQ(r.summary.searchedPixels, 400 * 400 - 40 * 40);
  // No WCS: the area from the pixel scale.
  EXPECT_DOUBLE_EQ(r.summary.searchedAreaDeg2, (400.0 * 400 - 40 * 40) * std::pow(0.25 / 3600, 2));
  EXPECT_DOUBLE_EQ(r.summary.rejectedFraction(), 1.0 - 3.0 / 11.0);
  ASSERT_EQ(r.candidates.size(), 2U);

  // The arc: best row 1 (P 0.5 beats 0.4), levels 2 and 3, in both spaces (row 2 has 0.25).
  const Candidate& arc = r.candidates[0];
  EXPECT_EQ(arc.row, 1U);
  EXPECT_EQ(arc.rows, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(arc.passedLevels, (std::vector<int>{2, 3}));
  EXPECT_DOUBLE_EQ(arc.probability, 0.5);
  EXPECT_DOUBLE_EQ(arc.contourLevel, 0.5);
  EXPECT_EQ(arc.spaces, 3U);
  ASSERT_TRUE(arc.lens);
  EXPECT_EQ(arc.lens->row, 3U);
  EXPECT_DOUBLE_EQ(arc.lens->einsteinRadiusArcsec, 10 * kScale);
  EXPECT_EQ(arc.flags & kCandidateDarkLens, 0);
  EXPECT_NE(arc.flags & kCandidateNoWcs, 0);
  EXPECT_NE(arc.flags & kCandidateNoCurvature, 0);  // no footprints given
  EXPECT_TRUE(arc.name.empty());

  // Row 11: alone, P 0.4; its concave side (+b of theta = 45 deg, ARC_SIDE -1) has no galaxy.
  const Candidate& alone = r.candidates[1];
  EXPECT_EQ(alone.row, 11U);
  EXPECT_DOUBLE_EQ(alone.probability, 0.4);
  EXPECT_DOUBLE_EQ(alone.contourLevel, 0.9);
  EXPECT_EQ(alone.spaces, 3U);
  EXPECT_FALSE(alone.lens);
  EXPECT_NE(alone.flags & kCandidateDarkLens, 0);

  ASSERT_EQ(r.summary.spaces.size(), 2U);
  EXPECT_EQ(r.summary.spaces[0].candidates, 2);
  EXPECT_EQ(r.summary.spaces[0].rowsPassed, 2);  // rows 2 and 11
  EXPECT_EQ(r.summary.spaces[1].rowsPassed, 3);
}

TEST(Search, TheGridsOwnSpaceAndMissingColumns) {
  const Table catalog = catalogOf(
      {{50, 50, 1, 1, 0, 90, 5.0, 0.5, 0, 1, 0.15}, {80, 50, 1, 2, 0, 90, 5.0, 0.5, 0, 1, 0.25}});
  SavedGrid grid = arcnessGrid();
  grid.provenance.searchSpace = "strong";
  grid.provenance.searchSpaceExpression = "ARCNESS > 0.2";
  const SearchMask mask(100, 100, {});
  SearchSettings s;
  s.pixelScaleArcsec = kScale;
  SearchInput in{&catalog, &grid, &mask, nullptr, nullptr, nullptr};
  const SearchResult r = searchCandidates(in, s);
  ASSERT_EQ(r.candidates.size(), 1U);
  EXPECT_EQ(r.candidates[0].row, 1U);

  Table lacking({ColumnSpec{"X_IMAGE", "", "", "", ColumnType::Float64, "", 1}});
  in.catalog = &lacking;
  EXPECT_THROW(searchCandidates(in, s), ConfigError);
  in.catalog = &catalog;
  s.pixelScaleArcsec = 0;
  EXPECT_THROW(searchCandidates(in, s), ConfigError);
}

// An arc too little curved for its side to be known (|ARCNESS| < LENS_SIDE_ARCNESS): the lens is
// the nearest galaxy, here on the side ARC_SIDE calls convex; with the rule off, the concave one.
TEST(Search, NearestGalaxyWhenTheSideIsUnknown) {
  const Table catalog = catalogOf({{100, 100, 1, 1, 0, 90, 5.0, 0.5, 0, 1, 0.02},
                                   {100, 90, 1, 2, 0, 300, 4.0, 0.1, 0, 0, 0.01},
                                   {100, 115, 1, 3, 0, 300, 4.0, 0.1, 0, 0, 0.01}});
  GridBinning binning({GridAxis{"ARCNESS", 0.0, 0.03, 1}});
  OccupationGrid occupation = OccupationGrid::fromCounts(binning, {{0, 3}}, 0, 0);
  const Contour contour = occupation.contour(0.9);
  const SavedGrid grid{std::move(occupation), contour, GridProvenance{}};
  const SearchMask mask(200, 200, {});
  SearchSettings s;
  s.pixelScaleArcsec = kScale;
  SearchInput in{&catalog, &grid, &mask, nullptr, nullptr, nullptr};
  // Rows 1 and 2 (ARCNESS 0.01) pass too; the first candidate is row 0 (ties: lower row).
  SearchResult r = searchCandidates(in, s);
  ASSERT_EQ(r.candidates.size(), 3U);
  ASSERT_EQ(r.candidates[0].row, 0U);
  ASSERT_TRUE(r.candidates[0].lens);
  EXPECT_EQ(r.candidates[0].lens->row, 1U);
  EXPECT_DOUBLE_EQ(r.candidates[0].lens->einsteinRadiusArcsec, 10 * kScale);
  EXPECT_NE(r.candidates[0].flags & kCandidateSideUnknown, 0);
  s.sideMinArcness = 0.0;
  r = searchCandidates(in, s);
  ASSERT_TRUE(r.candidates[0].lens);
  EXPECT_EQ(r.candidates[0].lens->row, 2U);
  EXPECT_EQ(r.candidates[0].flags & kCandidateSideUnknown, 0);
}

}  // namespace
}  // namespace octarc
