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
  EXPECT_DOUBLE_EQ(arc.lens->distanceArcsec, 10 * kScale);
  // No circle, no counter-image (the decoy lies on the arc's side of the lens): the distance as
  // that of the outer image of a double.
  EXPECT_EQ(arc.lens->thetaEMethod, ThetaEMethod::kDistance);
  EXPECT_DOUBLE_EQ(arc.lens->einsteinRadiusArcsec, 10 * kScale / kOuterImageDistanceRatio);
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

  // LENS_SCORE. Rows scored (searched, above the S/N floor, resolved): 0-4, 7, 8, 10 and 11.
  // With one row added to each occupied bin, bin 1 holds 2 of 12 rows and bin 2 holds 3 (rows 2,
  // 11): likelihood ratios 0.5 / (2/12) = 3 and 0.4 / (3/12) = 1.6. The prior: LENS_DENSITY 1
  // per deg2 over the searched area, one row per system, among the 9 rows.
  EXPECT_EQ(r.summary.rowsScored, 9);
  const double prior = r.summary.searchedAreaDeg2 / 9.0;
  EXPECT_DOUBLE_EQ(r.summary.priorFraction, prior);
  auto posterior = [&](double ratio) {
    const double odds = ratio * prior / (1.0 - prior);
    return odds / (1.0 + odds);
  };
  EXPECT_NEAR(arc.lensScore / posterior(3.0), 1.0, 1e-12);
  EXPECT_NEAR(alone.lensScore / posterior(1.6), 1.0, 1e-12);

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
  SearchInput in{&catalog, &grid, &mask, nullptr, nullptr, nullptr, nullptr, nullptr};
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
  SearchInput in{&catalog, &grid, &mask, nullptr, nullptr, nullptr, nullptr, nullptr};
  // Rows 1 and 2 (ARCNESS 0.01) pass too; the first candidate is row 0 (ties: lower row).
  SearchResult r = searchCandidates(in, s);
  ASSERT_EQ(r.candidates.size(), 3U);
  ASSERT_EQ(r.candidates[0].row, 0U);
  ASSERT_TRUE(r.candidates[0].lens);
  EXPECT_EQ(r.candidates[0].lens->row, 1U);
  EXPECT_DOUBLE_EQ(r.candidates[0].lens->distanceArcsec, 10 * kScale);
  EXPECT_NE(r.candidates[0].flags & kCandidateSideUnknown, 0);
  s.sideMinArcness = 0.0;
  r = searchCandidates(in, s);
  ASSERT_TRUE(r.candidates[0].lens);
  EXPECT_EQ(r.candidates[0].lens->row, 2U);
  EXPECT_EQ(r.candidates[0].flags & kCandidateSideUnknown, 0);
}

// Colours and the dark-lens pair on a hand-made scene (0-based pixels of a 100 x 100 image):
// an arc of radius 10 about (50, 50) spanning +-40 degrees about +x, 10 ADU per pixel in the
// measurement band and 5 in band g (colour g - r = 2.5 log10 2 = 0.7526); a 3 x 3 counter-image
// on the far side at (45, 50), 40 and 20 ADU (the same colour) or 40 and 40 (colour 0); and, when
// asked, a 3 x 3 red lens at the centre, 40 and 10 ADU (colour 2.5 log10 4 = 1.5051).
struct ColourScene {
  ImageF r{100, 100, 0.0f}, g{100, 100, 0.0f};
  SegmentationRuns footprints{100, 100, 1};
  std::vector<RowValues> rows;
  std::size_t arcPixels = 0;

  ColourScene(double counterG, bool lens) {
    std::vector<Segment> segments(1);
    double sx = 0, sy = 0;
    for (int y = 35; y <= 65; ++y) {
      for (int x = 50; x <= 65; ++x) {
        const double dx = x - 50, dy = y - 50;
        if (std::fabs(std::hypot(dx, dy) - 10.0) > 0.7 || std::fabs(std::atan2(dy, dx)) > 0.698) {
          continue;
        }
        r(x, y) = 10;
        g(x, y) = 5;
        segments[0].pixels.push_back(y * 100 + x);
        sx += x;
        sy += y;
      }
    }
    arcPixels = segments[0].pixels.size();
    segments[0].number = 1;
    // The arc: its centroid (1-based), major axis along y (e1 < 0), concave side -x (ARC_SIDE +1).
    rows.push_back({sx / double(arcPixels) + 1, sy / double(arcPixels) + 1, 1, 1, 0, 90, 5.0, -0.5,
                    0, 1, 0.15});
    auto block = [&](int x0, int y0, int number, float rValue, float gValue) {
      Segment seg;
      seg.number = number;
      for (int y = y0 - 1; y <= y0 + 1; ++y) {
        for (int x = x0 - 1; x <= x0 + 1; ++x) {
          r(x, y) = rValue;
          g(x, y) = gValue;
          seg.pixels.push_back(y * 100 + x);
        }
      }
      segments.push_back(seg);
      // Compact and faint in S/N: never a candidate itself.
      rows.push_back({x0 + 1.0, y0 + 1.0, 1, number, 0, 10, 1.5, 0, 0, 0, 0.01});
    };
    block(45, 50, 2, 40, float(counterG));
    if (lens) block(50, 50, 3, 40, 10);
    footprints.add(segments);
  }
};

// `lensLightOf` (optional): the rows' lens-light origins, the residual being the scene itself.
SearchResult searchColours(const ColourScene& scene, const Table& catalog, SearchSettings s,
                           const std::vector<std::int64_t>* lensLightOf = nullptr) {
  static const SavedGrid grid = arcnessGrid();
  static const SearchMask mask(100, 100, {});
  BandImage r, g;
  r.pixels = &scene.r;
  g.pixels = &scene.g;
  r.sigmaAdu = g.sigmaAdu = 1.0;
  r.magZeropoint = g.magZeropoint = 30.0;
  const std::vector<BandImage> bands = {g};
  s.pixelScaleArcsec = kScale;
  s.lensRadiusArcsec = 5.0;  // 20 px: the counter-image, 14 px from the arc, is within reach
  s.colourBands = {"g"};
  SearchInput in{&catalog, &grid, &mask, nullptr, &scene.footprints, &scene.r};
  in.measurementBand = &r;
  in.bands = &bands;
  in.lensLightOf = lensLightOf;
  in.residualPixels = lensLightOf != nullptr ? &scene.r : nullptr;
  return searchCandidates(in, s);
}

TEST(Search, DarkLensPairOfTheSameColour) {
  const ColourScene scene(20, false);
  const Table catalog = catalogOf(scene.rows);
  const SearchResult result = searchColours(scene, catalog, SearchSettings());
  ASSERT_EQ(result.candidates.size(), 1U);
  const Candidate& c = result.candidates[0];
  ASSERT_TRUE(c.curvature);
  // About the ring's centre (51, 51), 1-based; a thin, pixelised 80-degree arc pulls it by ~1 px.
  EXPECT_NEAR(c.curvature->xCentre, 51.0, 1.5);
  EXPECT_NEAR(c.curvature->yCentre, 51.0, 1.5);
  EXPECT_NEAR(c.curvature->radius, 10.0, 1.5);
  // The counter-image lies on the concave side within LENS_RADIUS, the lens findLens would take;
  // the criterion holds: no lens, flags 1 and 32.
  EXPECT_FALSE(c.lens);
  EXPECT_TRUE(c.lensMags.empty());
  EXPECT_EQ(c.flags & (kCandidateDarkLens | kCandidateDarkLensPair),
            kCandidateDarkLens | kCandidateDarkLensPair);
  ASSERT_TRUE(c.secondary);
  EXPECT_EQ(c.secondary->row, 1U);
  EXPECT_DOUBLE_EQ(c.secondary->xPix, 46.0);
  EXPECT_DOUBLE_EQ(c.secondary->yPix, 51.0);
  // The arc's magnitudes: n pixels of 10 and 5 ADU, noise 1 ADU per pixel.
  const double n = double(scene.arcPixels);
  ASSERT_EQ(c.arcMags.size(), 2U);
  EXPECT_NEAR(c.arcMags[0].mag, 30.0 - 2.5 * std::log10(10 * n), 1e-9);
  EXPECT_NEAR(c.arcMags[0].magErr, 1.086 * std::sqrt(n) / (10 * n), 1e-9);
  EXPECT_NEAR(c.arcMags[1].mag, 30.0 - 2.5 * std::log10(5 * n), 1e-9);
  EXPECT_NEAR(c.arcMags[1].mag - c.arcMags[0].mag, 0.7526, 1e-4);
}

TEST(Search, NoDarkLensPairWithAnotherColourOrALensAtTheCentre) {
  // A counter-image of colour 0 against the arc's 0.75: findLens's choice stands.
  const ColourScene blue(40, false);
  const Table blueCatalog = catalogOf(blue.rows);
  SearchResult result = searchColours(blue, blueCatalog, SearchSettings());
  ASSERT_EQ(result.candidates.size(), 1U);
  ASSERT_TRUE(result.candidates[0].lens);
  EXPECT_EQ(result.candidates[0].lens->row, 1U);
  EXPECT_EQ(result.candidates[0].flags & kCandidateDarkLensPair, 0);
  EXPECT_FALSE(result.candidates[0].secondary);

  // A red galaxy at the centre: it is the lens, and the pair is not dark.
  const ColourScene lensed(20, true);
  const Table catalog = catalogOf(lensed.rows);
  result = searchColours(lensed, catalog, SearchSettings());
  ASSERT_EQ(result.candidates.size(), 1U);
  const Candidate& c = result.candidates[0];
  ASSERT_TRUE(c.lens);
  EXPECT_EQ(c.lens->row, 2U);
  EXPECT_EQ(c.flags & (kCandidateDarkLens | kCandidateDarkLensPair), 0);
  // The 3 x 3 block on the far side, 5 px from the lens, is the arc's counter-image: theta_E is
  // the mean of the two images' distances to the lens.
  EXPECT_EQ(c.lens->thetaEMethod, ThetaEMethod::kCounterImage);
  const double arcDistance = std::hypot(catalog.value(0, 0) - 51.0, catalog.value(0, 1) - 51.0);
  EXPECT_DOUBLE_EQ(c.lens->distanceArcsec, arcDistance * kScale);
  EXPECT_NEAR(c.lens->einsteinRadiusArcsec, 0.5 * (arcDistance + 5.0) * kScale, 1e-12);
  EXPECT_EQ(c.flags & kCandidateLensInArc, 0);
  ASSERT_EQ(c.lensMags.size(), 2U);
  EXPECT_NEAR(c.lensMags[0].mag, 30.0 - 2.5 * std::log10(360.0), 1e-9);
  EXPECT_NEAR(c.lensMags[1].mag - c.lensMags[0].mag, 2.5 * std::log10(4.0), 1e-9);
}

TEST(Search, ColourCutOnArcMinusLensColour) {
  // Arc minus lens colour: 2.5 log10 2 - 2.5 log10 4 = -0.7526.
  const ColourScene lensed(20, true);
  const Table catalog = catalogOf(lensed.rows);
  SearchSettings s;
  s.reportSpaces = {SearchSpace("any", "ARCNESS > 0")};
  s.colourCut = ColourCut{"g", -0.7};
  SearchResult result = searchColours(lensed, catalog, s);
  EXPECT_EQ(result.candidates.size(), 1U);
  EXPECT_EQ(result.summary.removedByColourCut, 0);
  s.colourCut = ColourCut{"g", -0.8};
  result = searchColours(lensed, catalog, s);
  EXPECT_TRUE(result.candidates.empty());
  EXPECT_EQ(result.summary.removedByColourCut, 1);
  EXPECT_EQ(result.summary.candidates, 0);
  EXPECT_EQ(result.summary.spaces[0].candidates, 0);
  // Without a lens (the dark pair) there is no lens colour: kept.
  const ColourScene dark(20, false);
  const Table darkCatalog = catalogOf(dark.rows);
  result = searchColours(dark, darkCatalog, s);
  EXPECT_EQ(result.candidates.size(), 1U);
  EXPECT_EQ(result.summary.removedByColourCut, 0);
  // A band the search does not have is a configuration error.
  s.colourCut = ColourCut{"i", 0.0};
  EXPECT_THROW(searchColours(dark, darkCatalog, s), ConfigError);
}

// LENS_LIGHT LOCAL: the residual's rows (lensLightOf = the fitted galaxy's row) add to the
// image's. Row 0, an arc of the image, concave side +y; row 1, the fitted galaxy (image);
// row 2, the galaxy's remains in the residual, nearer the arc on its concave side; row 3, an arc
// found in the residual only; row 4, row 0 seen again in the residual.
TEST(Search, LocalResidualRowsAddArcsNotLensesOrObjects) {
  const Table catalog = catalogOf({{100, 100, 1, 1, 0, 90, 5.0, 0.5, 0, 1, 0.15},
                                   {100, 110, 1, 2, 0, 300, 6.0, 0.1, 0, 0, 0.01},
                                   {100, 106, 1, 10, 0, 60, 3.0, 0.1, 0, 0, 0.01},
                                   {130, 100, 1, 11, 0, 90, 5.0, 0.5, 0, 1, 0.25},
                                   {100.5, 100, 1, 12, 0, 90, 5.0, 0.5, 0, 1, 0.15}});
  const SavedGrid grid = arcnessGrid();
  const SearchMask mask(200, 200, {});
  SearchSettings s;
  s.pixelScaleArcsec = kScale;
  s.lensRadiusArcsec = 5.0;
  const std::vector<std::int64_t> lensLightOf = {kNotLensLightRow, kNotLensLightRow, 1, 1, 1};
  SearchInput in;
  in.catalog = &catalog;
  in.grid = &grid;
  in.mask = &mask;
  in.lensLightOf = &lensLightOf;
  in.residualRowsAreExtra = true;
  const SearchResult r = searchCandidates(in, s);
  EXPECT_EQ(r.summary.rowsSearched, 5);
  EXPECT_EQ(r.summary.objectsSearched, 2);  // the image's two objects
  // Row 4 is row 0's twin (0.5 px), dropped; rows 0 and 3 remain. By LENS_SCORE row 3 first:
  // of the 5 rows scored (one added per bin, 8 in all), bin 1 holds rows 0 and 4, 3 of 8
  // (ratio 0.5 / (3/8) = 1.33), bin 2 row 3 alone, 2 of 8 (0.4 / (2/8) = 1.6).
  ASSERT_EQ(r.candidates.size(), 2U);
  EXPECT_EQ(r.candidates[1].row, 0U);
  ASSERT_TRUE(r.candidates[1].lens);
  EXPECT_EQ(r.candidates[1].lens->row, 1U);  // the image's galaxy, not its residual
  EXPECT_EQ(r.candidates[1].flags & kCandidateLensLight, 0);
  EXPECT_EQ(r.candidates[0].row, 3U);
  ASSERT_TRUE(r.candidates[0].lens);
  EXPECT_EQ(r.candidates[0].lens->row, 1U);
  EXPECT_DOUBLE_EQ(r.candidates[0].lens->distanceArcsec, std::hypot(30.0, 10.0) * kScale);
  EXPECT_NE(r.candidates[0].flags & kCandidateLensLight, 0);

  // With the galaxy's fitted centre, the residual's arc is measured from it; the image's arc
  // keeps the catalog's centroid.
  const std::map<std::size_t, std::pair<double, double>> fitted = {{1, {100.0, 112.0}}};
  in.fittedCentres = &fitted;
  const SearchResult f = searchCandidates(in, s);
  ASSERT_EQ(f.candidates.size(), 2U);
  EXPECT_DOUBLE_EQ(f.candidates[1].lens->yPix, 110.0);
  EXPECT_EQ(f.candidates[0].lens->row, 1U);
  EXPECT_DOUBLE_EQ(f.candidates[0].lens->xPix, 100.0);
  EXPECT_DOUBLE_EQ(f.candidates[0].lens->yPix, 112.0);
  EXPECT_DOUBLE_EQ(f.candidates[0].lens->distanceArcsec, std::hypot(30.0, 12.0) * kScale);
}

// An arc found in a fitted galaxy's residual keeps that galaxy as its lens: the dark-lens pair
// criterion, which would take the counter-image for a sign of no lens, is not applied to it.
TEST(Search, ResidualArcKeepsItsFittedLensWithColours) {
  ColourScene scene(20, false);
  scene.rows.push_back({81, 81, 1, 3, 0, 300, 6.0, 0.1, 0, 0, 0.01});  // the fitted galaxy
  const Table catalog = catalogOf(scene.rows);
  const std::vector<std::int64_t> lensLightOf = {2, kNotLensLightRow, kLensOnlyRow};
  const SearchResult result = searchColours(scene, catalog, SearchSettings(), &lensLightOf);
  ASSERT_EQ(result.candidates.size(), 1U);
  const Candidate& c = result.candidates[0];
  EXPECT_NE(c.flags & kCandidateLensLight, 0);
  ASSERT_TRUE(c.lens);
  EXPECT_EQ(c.lens->row, 2U);
  EXPECT_EQ(c.flags & (kCandidateDarkLens | kCandidateDarkLensPair), 0);
  EXPECT_FALSE(c.secondary);
  EXPECT_NEAR(c.arcMags[1].mag - c.arcMags[0].mag, 0.7526, 1e-4);
}

// An arc blended with its lens: at level 1 one object whose centroid (100, 100) lies between the
// two; at levels 2-4 its brightest peak, the lens's core, 4 px off; at level 2 the arc too,
// 8 px off on the other side, so the blend curves towards the core (ARC_SIDE -1). The lens is
// the blend's peak (flag 64), the arc's distance that of its farthest passing row.
TEST(Search, ArcBlendedWithItsLensNamesTheBlendsPeak) {
  const Table catalog = catalogOf({
      {100, 100, 1, 1, 0, 90, 5.0, 0.5, 0, -1, 0.15},  // 0: the blend, concave side -y
      {100, 96, 2, 1, 1, 30, 2.0, 0.0, 0, 0, 0.01},    // 1: the lens core
      {100, 108, 2, 2, 1, 60, 3.5, 0.5, 0, 1, 0.25},   // 2: the arc, passes
      {100, 96, 3, 1, 1, 30, 1.5, 0.0, 0, 0, 0.01},    // 3: the core
      {100, 96.2, 4, 1, 1, 30, 1.5, 0.0, 0, 0, 0.01},  // 4: its peak
      {100, 80, 1, 2, 0, 300, 6.0, 0.1, 0, 0, 0.01},   // 5: a galaxy on the concave side
  });
  const SavedGrid grid = arcnessGrid();
  const SearchMask mask(200, 200, {});
  SearchSettings s;
  s.pixelScaleArcsec = kScale;
  s.lensRadiusArcsec = 6.0;
  SearchInput in;
  in.catalog = &catalog;
  in.grid = &grid;
  in.mask = &mask;
  const SearchResult r = searchCandidates(in, s);
  ASSERT_EQ(r.candidates.size(), 1U);
  const Candidate& c = r.candidates[0];
  EXPECT_EQ(c.rows, (std::vector<std::size_t>{0, 2}));
  ASSERT_TRUE(c.lens);
  EXPECT_EQ(c.lens->row, 4U);
  EXPECT_DOUBLE_EQ(c.lens->xPix, 100.0);
  EXPECT_DOUBLE_EQ(c.lens->yPix, 96.2);
  EXPECT_NE(c.flags & kCandidateLensInArc, 0);
  EXPECT_DOUBLE_EQ(c.lens->distanceArcsec, 11.8 * kScale);
  EXPECT_EQ(c.lens->thetaEMethod, ThetaEMethod::kDistance);
  EXPECT_DOUBLE_EQ(c.lens->einsteinRadiusArcsec, 11.8 * kScale / kOuterImageDistanceRatio);
}

}  // namespace
}  // namespace octarc
