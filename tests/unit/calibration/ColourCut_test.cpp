// The colour cut study on a hand-made systems table: which arcs count, the fraction kept at each
// MAX counted by hand (the arcs without both colours always kept, as the search keeps them), the
// smallest MAX for a completeness level, and bad settings.
#include "octarc/calibration/ColourCut.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "octarc/calibration/Weights.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

ColumnSpec doubleColumn(const char* name) {
  ColumnSpec c;
  c.name = name;
  c.type = ColumnType::Float64;
  return c;
}

constexpr const char* kArcs = "ARC_FOUND == 1 && ARCNESS > 0.1";

// Systems: (ARC_FOUND, ARCNESS, ARC_COLOUR_g, LENS_COLOUR_g).
Table colourTable(const std::vector<std::array<double, 4>>& rows) {
  Table t({doubleColumn("ARC_FOUND"), doubleColumn("ARCNESS"), doubleColumn("ARC_COLOUR_g"),
           doubleColumn("LENS_COLOUR_g")});
  for (const auto& r : rows) std::copy(r.begin(), r.end(), t.appendRow());
  return t;
}

TEST(ColourCut, FractionsKeptCountedByHand) {
  const double nan = std::nan("");
  // Ten arcs (ARC_FOUND 1, ARCNESS > 0.1): arc minus lens colours -1.0, -0.75, -0.75, -0.5,
  // -0.25, 0.0, 0.5 and 1.5 (exact in binary), and two without a lens colour. Three rows that are
  // not arcs, whatever their colours.
  const Table t = colourTable({{1, 0.12, 0.25, 1.25},
                               {1, 0.15, 0.5, 1.25},
                               {1, 0.20, 0.5, 1.25},
                               {1, 0.11, 0.75, 1.25},
                               {1, 0.13, 1.0, 1.25},
                               {1, 0.14, 1.0, 1.0},
                               {1, 0.18, 1.5, 1.0},
                               {1, 0.16, 2.5, 1.0},
                               {1, 0.12, 0.5, nan},
                               {1, 0.19, 0.5, nan},
                               {1, 0.05, 0.0, 2.0},   // arcness too low
                               {0, 0.30, 0.0, 2.0},   // no arc found
                               {1, nan, 0.0, 2.0}});  // no arcness: not an arc
  ColourCutSettings s;
  s.maxLoMag = -1.0;
  s.maxHiMag = 1.0;
  s.stepMag = 0.5;
  s.completenessLevels = {0.5, 0.8, 0.95, 0.2};
  const ColourCutStudy c = colourCutStudy(t, "g", kArcs, s);
  EXPECT_EQ(c.band, "g");
  EXPECT_EQ(c.arcs.count, 10);
  EXPECT_EQ(c.withColours, 8);
  // MAX -1.0, -0.5, 0.0, 0.5, 1.0: kept are the 2 without a colour plus those <= MAX (a value
  // equal to MAX is kept: the search removes only those above it).
  const std::int64_t kept[] = {2 + 1, 2 + 4, 2 + 6, 2 + 7, 2 + 7};
  ASSERT_EQ(c.rows.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_NEAR(c.rows[k].maxMag, -1.0 + 0.5 * double(k), 1e-12);
    EXPECT_EQ(c.rows[k].kept, kept[k]) << "MAX " << c.rows[k].maxMag;
    EXPECT_DOUBLE_EQ(c.rows[k].fraction.fraction, kept[k] / 10.0);
    const FractionInterval cp = clopperPearson(double(kept[k]), 10.0);
    EXPECT_NEAR(c.rows[k].fraction.lo, cp.lo, 1e-12);
    EXPECT_NEAR(c.rows[k].fraction.hi, cp.hi, 1e-12);
  }
  // 50 %: 5 arcs, 3 besides the two always kept: the third smallest difference, -0.75. 80 %: 6
  // besides them: 0.0. 95 %: ceil(9.5) = 10: all 8: 1.5. 20 %: the two alone: any MAX.
  ASSERT_EQ(c.levels.size(), 4u);
  EXPECT_DOUBLE_EQ(c.levels[0].maxMag, -0.75);
  EXPECT_DOUBLE_EQ(c.levels[1].maxMag, 0.0);
  EXPECT_DOUBLE_EQ(c.levels[2].maxMag, 1.5);
  EXPECT_EQ(c.levels[3].maxMag, -std::numeric_limits<double>::infinity());
}

// With SIM_WEIGHT: the fractions kept are weight sums, the levels reached by weight.
TEST(ColourCut, WeightedFractionsAndLevels) {
  ColumnSpec w = doubleColumn("SIM_WEIGHT");
  Table t({doubleColumn("ARC_FOUND"), doubleColumn("ARCNESS"), doubleColumn("ARC_COLOUR_g"),
           doubleColumn("LENS_COLOUR_g"), w});
  // Differences -0.5 (weight 1), 0.0 (weight 6), 0.5 (weight 2), one without colour (weight 1).
  const std::vector<std::array<double, 5>> rows = {{1, 0.2, 0.5, 1.0, 1.0},
                                                   {1, 0.2, 1.0, 1.0, 6.0},
                                                   {1, 0.2, 1.5, 1.0, 2.0},
                                                   {1, 0.2, 1.5, std::nan(""), 1.0}};
  for (const auto& r : rows) std::copy(r.begin(), r.end(), t.appendRow());
  ColourCutSettings s;
  s.maxLoMag = -0.5;
  s.maxHiMag = 0.5;
  s.stepMag = 0.5;
  s.completenessLevels = {0.5, 0.9, 0.1};
  const ColourCutStudy c = colourCutStudy(t, "g", kArcs, s);
  EXPECT_EQ(c.arcs.count, 4);
  EXPECT_DOUBLE_EQ(c.arcs.weightSum, 10.0);
  ASSERT_EQ(c.rows.size(), 3u);
  const double kept[] = {2.0, 8.0, 10.0};  // the colourless arc (1) plus those <= MAX
  const double n = 100.0 / 42.0;           // (sum w)^2 / sum w^2
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(c.rows[k].keptWeight, kept[k]);
    EXPECT_DOUBLE_EQ(c.rows[k].fraction.fraction, kept[k] / 10.0);
    const FractionInterval cp = clopperPearson(kept[k] / 10.0 * n, n);
    EXPECT_NEAR(c.rows[k].fraction.hi, cp.hi, 1e-12);
  }
  // 50 %: 5 of 10, 4 beyond the colourless arc: reached at 0.0 (1 + 6). 90 %: 9: at 0.5. 10 %:
  // the colourless arc alone: any MAX.
  EXPECT_DOUBLE_EQ(c.levels[0].maxMag, 0.0);
  EXPECT_DOUBLE_EQ(c.levels[1].maxMag, 0.5);
  EXPECT_EQ(c.levels[2].maxMag, -std::numeric_limits<double>::infinity());
}

TEST(ColourCut, MissingColumnsAndBadRangesAreNamed) {
  const Table t = colourTable({{1, 0.2, 0.5, 1.2}});
  ColourCutSettings s;
  try {
    colourCutStudy(t, "i", kArcs, s);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("ARC_COLOUR_i"), std::string::npos) << e.what();
  }
  s.stepMag = 0.0;
  EXPECT_THROW(colourCutStudy(t, "g", kArcs, s), ConfigError);
  s.stepMag = 0.1;
  s.maxHiMag = -2.0;
  try {
    checkColourCutSettings(s);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("COLOUR_CUT_MAX"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace octarc
