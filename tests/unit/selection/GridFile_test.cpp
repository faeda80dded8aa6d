// The grid file: a round trip of every field, what the file holds, fitsverify, the setup
// comparison, and files that are not (or no longer) a grid.
#include "octarc/selection/GridFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "SelectionTestSupport.h"
#include "TestCommands.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;
using test::expectError;

// The 3 x 2 grid of the scoring tests (probabilities 0.5, 0.25, 0.125, 0.125 in bins 0, 1, 3,
// 4), on the first and last default axes, with one sample outside and two undefined.
OccupationGrid gridToWrite() {
  const GridBinning b({GridAxis{"ARCNESS", 0.0, 0.3, 3}, GridAxis{"log10(SNR_ISO)", 1.0, 3.0, 2}});
  return OccupationGrid::fill(b, {{0.05, 0.05, 0.05, 0.05, 0.15, 0.15, 0.05, 0.15, 0.4, kNaN, 0.1},
                                  {1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 2.5, 2.5, 1.5, 1.5, kNaN}});
}

SurveySetup dlsSetup() {
  SurveySetup s;
  s.pixelScaleArcsec = 0.257;
  s.seeingFwhmArcsec = 0.9;
  s.gainElectronsPerAdu = 54.0;
  s.skySigmaAdu = 5.3;
  for (int i = 0; i < 15; ++i) s.thresholdsSigma.push_back(2.5 * std::pow(8.0, i / 14.0));
  s.minAreaPix = 5;
  s.populationFile =
      "/data/surveys/deep-lens-survey/calibration/relations/population-relations-2026.txt";
  s.seed = 18446744073709551557ULL;  // above 2^63
  s.systems = 90000;
  return s;
}

SavedGrid savedGrid() {
  OccupationGrid grid = gridToWrite();
  const Contour contour = grid.contour(0.8);
  return SavedGrid{
      std::move(grid), contour,
      GridProvenance{"strong", "ARCNESS > 0.15 && E_IMAGE > 0.6 && SNR_ISO > 40", dlsSetup(), {}}};
}

TEST(GridFile, RoundTripKeepsEveryField) {
  const std::string path = (test::scratchDir() / "grid.fits").string();
  saveGrid(path, savedGrid());
  const SavedGrid in = loadGrid(path);
  const SavedGrid out = savedGrid();
  ASSERT_EQ(in.grid.binning().dimensions(), 2);
  for (int a = 0; a < 2; ++a) {
    const GridAxis& x = in.grid.binning().axes()[std::size_t(a)];
    const GridAxis& y = out.grid.binning().axes()[std::size_t(a)];
    EXPECT_EQ(x.expression, y.expression);
    EXPECT_EQ(x.lo, y.lo);
    EXPECT_EQ(x.hi, y.hi);
    EXPECT_EQ(x.bins, y.bins);
  }
  EXPECT_EQ(in.grid.binnedCount(), 8);
  EXPECT_EQ(in.grid.outsideCount(), 1);
  EXPECT_EQ(in.grid.undefinedCount(), 2);
  ASSERT_EQ(in.grid.occupiedBins(), 4);
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_EQ(in.grid.bins()[r].index, out.grid.bins()[r].index);
    EXPECT_EQ(in.grid.bins()[r].count, out.grid.bins()[r].count);
    EXPECT_EQ(in.grid.bins()[r].probability, out.grid.bins()[r].probability);
    EXPECT_EQ(in.grid.bins()[r].cumulative, out.grid.bins()[r].cumulative);
  }
  EXPECT_EQ(in.contour.level, 0.8);
  EXPECT_EQ(in.contour.selectedBins, 3);
  EXPECT_EQ(in.contour.probability, 0.875);
  EXPECT_EQ(in.provenance.searchSpace, "strong");
  EXPECT_EQ(in.provenance.searchSpaceExpression, out.provenance.searchSpaceExpression);
  const SurveySetup& s = in.provenance.setup;
  const SurveySetup expected = dlsSetup();
  EXPECT_EQ(s.pixelScaleArcsec, 0.257);
  EXPECT_EQ(s.seeingFwhmArcsec, 0.9);
  EXPECT_EQ(s.gainElectronsPerAdu, 54.0);
  EXPECT_EQ(s.skySigmaAdu, 5.3);
  EXPECT_EQ(s.thresholdsSigma, expected.thresholdsSigma);  // every double exactly
  EXPECT_EQ(s.minAreaPix, 5);
  EXPECT_EQ(s.populationFile, expected.populationFile);
  EXPECT_EQ(s.seed, 18446744073709551557ULL);
  EXPECT_EQ(s.systems, 90000);
  EXPECT_TRUE(compareSetups(s, expected).empty());
}

TEST(GridFile, TheFileHoldsTheBinsInProbabilityOrder) {
  const std::string path = (test::scratchDir() / "grid.fits").string();
  saveGrid(path, savedGrid());
  EXPECT_EQ(listFitsTables(path), (std::vector<std::string>{"OCC_GRID"}));
  const FitsTable t = readFitsTable(path, "OCC_GRID");
  // Bins 0, 1, 3, 4 of the 3 x 2 grid are (0,0), (1,0), (0,1), (1,1).
  EXPECT_EQ(t.integers("BIN", 2), (std::vector<std::int64_t>{0, 0, 1, 0, 0, 1, 1, 1}));
  EXPECT_EQ(t.integers("COUNT"), (std::vector<std::int64_t>{4, 2, 1, 1}));
  EXPECT_EQ(t.doubles("PROB"), (std::vector<double>{0.5, 0.25, 0.125, 0.125}));
  EXPECT_EQ(t.doubles("CUMPROB"), (std::vector<double>{0.5, 0.75, 0.875, 1.0}));
  EXPECT_EQ(t.integers("SELECTED"), (std::vector<std::int64_t>{1, 1, 1, 0}));
  EXPECT_EQ(t.integer("GRIDDIM"), 2);
  EXPECT_EQ(t.text("AXEXPR2"), "log10(SNR_ISO)");
  EXPECT_EQ(t.number("AXHI1"), 0.3);
  EXPECT_EQ(t.number("PLEVEL"), 0.8);
  EXPECT_EQ(t.integer("NSELECT"), 3);
  EXPECT_EQ(t.integer("NTHRESH"), 15);
  EXPECT_EQ(t.number("THRESH1"), 2.5);
  if (test::haveFitsverify()) {
    const std::string report = (fs::path(path).parent_path() / "report.txt").string();
    std::system(("fitsverify -q '" + path + "' > '" + report + "' 2>&1").c_str());
    EXPECT_NE(test::readFile(report).find("verification OK"), std::string::npos)
        << test::readFile(report);
  }
}

TEST(GridFile, SaveRefusesAContourOfAnotherLevel) {
  SavedGrid s = savedGrid();
  s.contour.selectedBins = 2;  // the contour at 0.8 has 3 bins
  expectError<ConfigError>([&] { saveGrid((test::scratchDir() / "g.fits").string(), s); },
                           {"not the grid's contour at its level (3 bins)"});
}

// Rewrites the OCC_GRID table of a saved grid after `edit`.
template <typename Edit>
std::string editedGrid(const fs::path& dir, const std::string& name, Edit&& edit) {
  const std::string good = (dir / "good.fits").string();
  if (!fs::exists(good)) saveGrid(good, savedGrid());
  FitsTable t = readFitsTable(good, "OCC_GRID");
  edit(t);
  const std::string path = (dir / name).string();
  writeFitsTables(path, {t});
  return path;
}

void dropKeyword(FitsTable& t, const char* name) {
  std::erase_if(t.keywords, [&](const FitsKeyword& k) { return k.name == name; });
}

// Weights are stored and read back; a version 1 file (no WEIGHT column) has its counts as the
// weights; the axes dropped are recorded.
TEST(GridFile, WeightsRoundTripAndOldFilesWeighTheirCounts) {
  const fs::path dir = test::scratchDir();
  const GridBinning b({GridAxis{"ARCNESS", 0.0, 0.3, 3}});
  OccupationGrid grid = OccupationGrid::fill(b, {{0.05, 0.05, 0.15, 0.25}}, {1.0, 1.0, 6.0, 2.0});
  const Contour contour = grid.contour(0.7);
  SavedGrid saved{std::move(grid), contour, GridProvenance{"", "", dlsSetup(), {"E_IMAGE"}}};
  const std::string path = (dir / "weighted.fits").string();
  saveGrid(path, saved);
  const FitsTable t = readFitsTable(path, "OCC_GRID");
  EXPECT_EQ(t.integer("OCTGRID"), 2);
  EXPECT_EQ(t.doubles("WEIGHT"), (std::vector<double>{6.0, 2.0, 2.0}));
  EXPECT_EQ(t.integers("COUNT"), (std::vector<std::int64_t>{1, 2, 1}));
  EXPECT_EQ(t.doubles("PROB"), (std::vector<double>{0.6, 0.2, 0.2}));
  EXPECT_EQ(t.number("WBINNED"), 10.0);
  EXPECT_EQ(t.integer("NDROPAX"), 1);
  EXPECT_EQ(t.text("DROPAX1"), "E_IMAGE");
  const SavedGrid in = loadGrid(path);
  EXPECT_EQ(in.grid.binnedWeight(), 10.0);
  EXPECT_EQ(in.grid.bins()[0].weight, 6.0);
  EXPECT_EQ(in.grid.bins()[0].count, 1);
  EXPECT_EQ(in.provenance.droppedAxes, (std::vector<std::string>{"E_IMAGE"}));
  // Version 1: no WEIGHT, WBINNED or NDROPAX; the counts 4, 2, 1, 1 are the weights.
  const std::string old = editedGrid(dir, "version1.fits", [](FitsTable& t) {
    std::erase_if(t.columns, [](const FitsColumn& c) { return c.name == "WEIGHT"; });
    dropKeyword(t, "WBINNED");
    dropKeyword(t, "NDROPAX");
    for (FitsKeyword& k : t.keywords) {
      if (k.name == "OCTGRID") k.value = std::int64_t(1);
    }
  });
  const SavedGrid v1 = loadGrid(old);
  EXPECT_EQ(v1.grid.binnedWeight(), 8.0);
  EXPECT_EQ(v1.grid.bins()[0].weight, 4.0);
  EXPECT_EQ(v1.grid.bins()[0].probability, 0.5);
  EXPECT_TRUE(v1.provenance.droppedAxes.empty());
}

TEST(GridFile, FilesThatAreNotAGridNameWhatIsMissing) {
  const fs::path dir = test::scratchDir();
  FitsTable other;
  other.name = "LDAC_OBJECTS";
  other.columns = {FitsColumn{"NUMBER", "", "", "", 1, std::vector<std::int32_t>{1}, "", ""}};
  const std::string catalog = (dir / "catalog.fits").string();
  writeFitsTables(catalog, {other});
  expectError<IoError>([&] { loadGrid(catalog); },
                       {catalog,
                        "not an occupation grid (no OCC_GRID table; tables: "
                        "LDAC_OBJECTS)"});
  expectError<IoError>([&] { loadGrid((dir / "missing.fits").string()); }, {"missing.fits"});

  const std::string noMarker =
      editedGrid(dir, "marker.fits", [](FitsTable& t) { dropKeyword(t, "OCTGRID"); });
  expectError<IoError>([&] { loadGrid(noMarker); },
                       {noMarker + "[OCC_GRID]", "not an occupation grid (keyword OCTGRID"});
  const std::string noAxis =
      editedGrid(dir, "axis.fits", [](FitsTable& t) { dropKeyword(t, "AXHI2"); });
  expectError<IoError>([&] { loadGrid(noAxis); }, {noAxis + "[OCC_GRID]", "AXHI2 missing"});
  const std::string noSetup =
      editedGrid(dir, "setup.fits", [](FitsTable& t) { dropKeyword(t, "MINAREA"); });
  expectError<IoError>([&] { loadGrid(noSetup); }, {noSetup, "MINAREA missing"});
  const std::string noCounts = editedGrid(dir, "counts.fits", [](FitsTable& t) {
    std::erase_if(t.columns, [](const FitsColumn& c) { return c.name == "COUNT"; });
  });
  expectError<IoError>([&] { loadGrid(noCounts); }, {noCounts, "no column COUNT"});
}

// Setup and axis cards that octarc never writes are refused, naming the file, the card, its
// value and the range; an undefined setup value is an unknown one, as the writer puts it.
TEST(GridFile, CardsOutOfTheirRangeAreRefused) {
  const fs::path dir = test::scratchDir();
  const auto withCard = [&](const std::string& key, const FitsKeywordValue& value) {
    return editedGrid(dir, key + ".fits", [&](FitsTable& t) {
      for (FitsKeyword& k : t.keywords) {
        if (k.name == key) k.value = value;
      }
    });
  };
  struct Case {
    std::string key;
    FitsKeywordValue value;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"THRESH1", kNaN, "THRESH1 = nan is not a finite number > 0"},
      {"PIXSCALE", -0.25, "PIXSCALE = -0.25 is not undefined (unknown) or a finite number > 0"},
      {"SKYSIGMA", 0.0, "SKYSIGMA = 0 is not undefined (unknown) or a finite number > 0"},
      {"GAIN", -1.0, "GAIN = -1 is not undefined (unknown) or a finite number >= 0"},
      {"MINAREA", std::int64_t(-1), "MINAREA = -1 is not an integer from 0 to 2147483647"},
      {"NTHRESH", std::int64_t(100), "NTHRESH = 100 is not an integer from 0 to 99"},
      {"AXBINS1", std::int64_t(999999999), "AXBINS1 = 999999999 is not an integer from 1 to 1000"},
      {"NTHRESH", std::int64_t(-1), "NTHRESH = -1 is not an integer from 0 to 99"},
      {"GRIDDIM", std::int64_t(0), "GRIDDIM = 0 is not an integer from 1 to 99"},
      {"NOUTSIDE", std::int64_t(-1),
       "NOUTSIDE = -1 is not an integer from 0 to 9223372036854775807"},
      {"NUNDEF", std::int64_t(-2), "NUNDEF = -2 is not an integer from 0 to"},
      {"NDROPAX", std::int64_t(100), "NDROPAX = 100 is not an integer from 0 to 99"},
      // dlsSetup's levels are 2.5 * 8^(i / 14): THRESH2 equal to THRESH1 does not increase.
      {"THRESH2", 2.5, "THRESH2 = 2.5 is not above THRESH1 = 2.5 (the levels increase strictly)"},
      {"THRESH3", 2.0, "THRESH3 = 2 is not above THRESH2 = 2.9"},
  };
  for (const Case& c : cases) {
    const std::string path = withCard(c.key, c.value);
    expectError<IoError>([&] { loadGrid(path); }, {path + "[OCC_GRID]: " + c.message});
    fs::remove(path);  // a card may be tried twice
  }
  EXPECT_TRUE(std::isnan(loadGrid(withCard("SEEING", kNaN)).provenance.setup.seeingFwhmArcsec));
}

// The ends of the ranges are accepted: a gain of 0 (infinite), no levels and no minimum area
// (unknown), 1000 bins on an axis, 99 levels (THRESH99: the most two digits name).
TEST(GridFile, CardsAtTheEndsOfTheirRangeAreRead) {
  const fs::path dir = test::scratchDir();
  const auto withCard = [&](const std::string& key, const FitsKeywordValue& value) {
    return editedGrid(dir, key + ".fits", [&](FitsTable& t) {
      for (FitsKeyword& k : t.keywords) {
        if (k.name == key) k.value = value;
      }
    });
  };
  EXPECT_EQ(loadGrid(withCard("GAIN", 0.0)).provenance.setup.gainElectronsPerAdu, 0.0);
  EXPECT_TRUE(
      loadGrid(withCard("NTHRESH", std::int64_t(0))).provenance.setup.thresholdsSigma.empty());
  EXPECT_EQ(loadGrid(withCard("MINAREA", std::int64_t(0))).provenance.setup.minAreaPix, 0);

  // One axis of 1000 bins and 99 levels, as written; AXBINS1 = 1001 is refused.
  const GridBinning b({GridAxis{"ARCNESS", 0.0, 1.0, 1000}});
  OccupationGrid grid = OccupationGrid::fill(b, {{0.0005, 0.0015, 0.9995}});
  const Contour contour = grid.contour(0.8);
  SurveySetup setup = dlsSetup();
  setup.thresholdsSigma.clear();
  for (int i = 1; i <= 99; ++i) setup.thresholdsSigma.push_back(double(i));
  const std::string path = (dir / "wide.fits").string();
  saveGrid(path, SavedGrid{std::move(grid), contour, GridProvenance{"", "", setup, {}}});
  const SavedGrid wide = loadGrid(path);
  EXPECT_EQ(wide.grid.binning().axes()[0].bins, 1000);
  EXPECT_EQ(wide.grid.bins().size(), 3u);
  ASSERT_EQ(wide.provenance.setup.thresholdsSigma.size(), 99u);
  EXPECT_EQ(wide.provenance.setup.thresholdsSigma.back(), 99.0);

  FitsTable t = readFitsTable(path, "OCC_GRID");
  for (FitsKeyword& k : t.keywords) {
    if (k.name == "AXBINS1") k.value = std::int64_t(1001);
  }
  const std::string tooWide = (dir / "too-wide.fits").string();
  writeFitsTables(tooWide, {t});
  expectError<IoError>([&] { loadGrid(tooWide); },
                       {tooWide + "[OCC_GRID]: AXBINS1 = 1001 is not an integer from 1 to 1000"});
}

TEST(GridFile, InconsistentGridFilesAreRefused) {
  const fs::path dir = test::scratchDir();
  // A count and its weight (unit weights: the same).
  auto setCount = [](FitsTable& t, std::size_t row, std::int64_t value) {
    for (FitsColumn& c : t.columns) {
      if (c.name == "COUNT") std::get<std::vector<std::int64_t>>(c.values)[row] = value;
      if (c.name == "WEIGHT") std::get<std::vector<double>>(c.values)[row] = double(value);
    }
  };
  // The last two bins swapped counts' order: 4, 2, 1, 3 is not a probability order.
  const std::string order = editedGrid(dir, "order.fits", [&](FitsTable& t) { setCount(t, 3, 3); });
  expectError<IoError>([&] { loadGrid(order); }, {order + "[OCC_GRID]", "out of probability"});
  const std::string total = editedGrid(dir, "total.fits", [&](FitsTable& t) { setCount(t, 0, 5); });
  expectError<IoError>([&] { loadGrid(total); },
                       {"NBINNED = 8 but the bins table gives 9 binned arcs"});
  const std::string weight = editedGrid(dir, "weight.fits", [&](FitsTable& t) {
    for (FitsKeyword& k : t.keywords) {
      if (k.name == "WBINNED") k.value = 9.5;
    }
  });
  expectError<IoError>([&] { loadGrid(weight); },
                       {"WBINNED = 9.5 but the bins table gives 8 binned weight"});
  const std::string bin = editedGrid(dir, "bin.fits", [](FitsTable& t) {
    for (FitsColumn& c : t.columns) {
      if (c.name == "BIN") std::get<std::vector<std::int32_t>>(c.values)[2] = 3;
    }
  });
  expectError<IoError>([&] { loadGrid(bin); },
                       {bin + "[OCC_GRID]", "row 2: bin index 3 outside axis 1's 0..2"});
  const std::string selected = editedGrid(dir, "selected.fits", [](FitsTable& t) {
    for (FitsColumn& c : t.columns) {
      if (c.name == "SELECTED") std::get<std::vector<std::int16_t>>(c.values)[3] = 1;
    }
  });
  expectError<IoError>([&] { loadGrid(selected); },
                       {"row 4: SELECTED disagrees with the contour at PLEVEL"});
  const std::string range = editedGrid(dir, "range.fits", [](FitsTable& t) {
    for (FitsKeyword& k : t.keywords) {
      if (k.name == "AXLO1") k.value = 0.5;
    }
  });
  expectError<IoError>([&] { loadGrid(range); }, {range + "[OCC_GRID]", "grid axis 1", "lo < hi"});
}

TEST(SurveySetup, DifferencesBeyondTheTolerancesAreWarned) {
  const SurveySetup grid = dlsSetup();
  SurveySetup search = grid;
  search.populationFile = "other.txt";  // provenance: never compared
  search.seed = 7;
  search.systems = 10;
  search.seeingFwhmArcsec = 0.95;  // 5.6% apart: within 10%
  EXPECT_TRUE(compareSetups(grid, search).empty());

  search.pixelScaleArcsec = 0.2;      // (0.257 - 0.2) / 0.257 = 22.179%
  search.seeingFwhmArcsec = 1.2;      // 33.333%
  search.gainElectronsPerAdu = 60.0;  // 11.111%
  search.skySigmaAdu = 5.0;           // 5.6604%: within 10%
  search.minAreaPix = 6;
  search.thresholdsSigma[2] *= 1.02;
  const std::vector<std::string> w = compareSetups(grid, search);
  ASSERT_EQ(w.size(), 5u);
  EXPECT_EQ(w[0],
            "pixel scale: made for 0.257 arcsec/px, the search has 0.2 "
            "(22.179% apart, tolerance 1%)");
  EXPECT_EQ(w[1],
            "seeing FWHM: made for 0.9 arcsec, the search has 1.2 (33.3333% "
            "apart, tolerance 10%)");
  EXPECT_EQ(w[2],
            "gain: made for 54 e-/ADU, the search has 60 (11.1111% apart, "
            "tolerance 10%)");
  EXPECT_EQ(w[3], "DETECT_MINAREA: made for 5 pixels, the search has 6");
  EXPECT_NE(w[4].find("threshold 3: "), std::string::npos) << w[4];
  EXPECT_NE(w[4].find("(2% apart, tolerance 1%)"), std::string::npos) << w[4];

  // Another number of levels; and what the search does not know is not compared.
  SurveySetup fewer;
  fewer.thresholdsSigma = {3.0, 6.0};
  const std::vector<std::string> levels = compareSetups(grid, fewer);
  ASSERT_EQ(levels.size(), 1u);
  EXPECT_EQ(levels[0], "thresholds: made for 15 levels, the search has 2");
  EXPECT_TRUE(compareSetups(grid, SurveySetup{}).empty());
  // Tighter tolerances make the seeing of 0.95 a difference.
  SurveySetup close = grid;
  close.seeingFwhmArcsec = 0.95;
  SetupTolerances strict;
  strict.seeingFwhm = 0.05;
  EXPECT_EQ(compareSetups(grid, close, strict).size(), 1u);
}

}  // namespace
}  // namespace octarc
