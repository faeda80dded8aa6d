// The candidate catalog from a hand-made catalog and search result: every value traced to the
// catalog row, the candidate or the summary it comes from, as FITS table and ASCII_HEAD text.
#include "octarc/search/CandidateTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "octarc/measure/Registry.h"

namespace octarc {
namespace {

// Catalog rows: 0 the first candidate's arc, 1 its lens, 2 the second candidate's arc. No
// MAGERR_ISO, ANTIARCNESS, SKEW_MAJOR, SKEW_MINOR or ARC_SIDE column.
Table handCatalog() {
  using T = ColumnType;
  Table t({{"NUMBER", "", "", "", T::Int32, "%6d"},
           {"THRESH_LEVEL", "", "", "", T::Int16, "%3d"},
           {"X_IMAGE", "", "pixel", "", T::Float32, "%10.3f"},
           {"Y_IMAGE", "", "pixel", "", T::Float32, "%10.3f"},
           {"MAG_ISO", "", "mag", "", T::Float32, "%8.4f"},
           {"SNR_ISO", "", "", "", T::Float32, "%10.2f"},
           {"ARCNESS", "", "", "", T::Float32, "%8.4f"},
           {"E_IMAGE", "", "", "", T::Float32, "%7.4f"},
           {"A_IMAGE", "", "pixel", "", T::Float32, "%9.3f"},
           {"B_IMAGE", "", "pixel", "", T::Float32, "%9.3f"},
           {"THETA_IMAGE", "", "deg", "", T::Float32, "%5.1f"},
           {"FLAGS", "", "", "", T::Int16, "%3d"}});
  const std::vector<std::vector<double>> rows = {
      {3, 2, 10.5, 20.25, 21.5, 55, 0.1875, 0.75, 4, 1.5, 30, 2},
      {7, 1, 15.5, 25.5, 19.0, 300, 0.01, 0.1, 6, 5, -10, 0},
      {4, 3, 100.0, 50.0, 22.25, 42, 0.125, 0.625, 3, 1, 90, 0}};
  for (const auto& r : rows) {
    double* out = t.appendRow();
    for (std::size_t c = 0; c < r.size(); ++c) out[c] = r[c];
  }
  return t;
}

SearchResult handResult() {
  SearchResult r;
  Candidate a;
  a.row = 0;
  a.rows = {0};
  a.passedLevels = {2, 3};
  a.spaces = 1;
  a.probability = 0.5;
  a.contourLevel = 0.75;
  a.name = "OCTARC J095950.40+021000.0";
  a.raDeg = 149.96;
  a.decDeg = 2.1666666666666667;
  a.curvature = CircleFit{12.0, 14.0, 6.5};
  a.lens = CandidateLens{1, 15.5, 25.5, 149.961, 2.167, 1.75, ThetaEMethod::kCurvature, 2.5};
  Candidate b;
  b.row = 2;
  b.rows = {2};
  b.passedLevels = {3};
  b.probability = 0.25;
  b.contourLevel = 0.5;
  b.flags = kCandidateDarkLens | kCandidateNoWcs;
  r.candidates = {a, b};
  r.summary.rowsSearched = 40;
  r.summary.objectsSearched = 10;
  r.summary.rowsSelected = 4;
  r.summary.candidates = 2;
  r.summary.searchedAreaDeg2 = 0.01;
  r.summary.searchedPixels = 5000;
  r.summary.spaces = {{"arcs", "ARCNESS > 0.15", 1, 3}};
  return r;
}

TEST(CandidateTable, ObjectsTableValuesComeFromRowCandidateAndSummary) {
  const Table catalog = handCatalog();
  const SearchResult result = handResult();
  SearchSettings settings;
  settings.pixelScaleArcsec = 0.25;
  settings.levelCount = 4;
  const FitsTable t = candidateObjectsTable(catalog, result, settings);
  EXPECT_EQ(t.name, "LDAC_OBJECTS");
  ASSERT_EQ(t.rows(), 2);
  // The column list is candidateColumns(), in order, with its units.
  const std::vector<CandidateColumnSpec> specs = candidateColumns({});
  ASSERT_EQ(t.columns.size(), specs.size());
  for (std::size_t c = 0; c < specs.size(); ++c) {
    EXPECT_EQ(t.columns[c].name, specs[c].spec.name);
    EXPECT_EQ(t.columns[c].unit, specs[c].spec.unit) << specs[c].spec.name;
  }
  EXPECT_EQ(t.columns.front().name, "NUMBER");
  EXPECT_EQ(t.column("X_IMAGE").unit, "pixel");
  EXPECT_EQ(t.column("THETA_E").unit, "arcsec");

  EXPECT_EQ(t.integers("NUMBER"), (std::vector<std::int64_t>{1, 2}));  // by probability
  EXPECT_EQ(t.strings("NAME"), (std::vector<std::string>{"OCTARC J095950.40+021000.0", ""}));
  EXPECT_EQ(t.doubles("ALPHA_J2000")[0], 149.96);
  EXPECT_TRUE(std::isnan(t.doubles("ALPHA_J2000")[1]));
  EXPECT_EQ(t.strings("RA_SEX")[0], "09:59:50.40");  // 149.96 / 15 = 9 h 59 m 50.40 s
  EXPECT_EQ(t.strings("DEC_SEX")[0], "+02:10:00.0");
  // From the best rows.
  EXPECT_EQ(t.doubles("X_IMAGE"), (std::vector<double>{10.5, 100.0}));
  EXPECT_EQ(t.doubles("Y_IMAGE"), (std::vector<double>{20.25, 50.0}));
  EXPECT_EQ(t.integers("THRESH_LEVEL"), (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(t.integers("OBJ_NUMBER"), (std::vector<std::int64_t>{3, 4}));
  EXPECT_EQ(t.doubles("MAG_ISO"), (std::vector<double>{21.5, 22.25}));
  EXPECT_EQ(t.doubles("ARCNESS"), (std::vector<double>{0.1875, 0.125}));
  EXPECT_EQ(t.integers("FLAGS"), (std::vector<std::int64_t>{2, 0}));
  // Columns the catalog lacks: NaN, 0 in an integer column.
  for (const char* absent : {"MAGERR_ISO", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR"}) {
    for (double v : t.doubles(absent)) EXPECT_TRUE(std::isnan(v)) << absent;
  }
  EXPECT_EQ(t.integers("ARC_SIDE"), (std::vector<std::int64_t>{0, 0}));
  // From the candidates.
  // LEVELS: one element per level of the run, the passed levels first, then 0.
  EXPECT_EQ(t.column("LEVELS").repeat, 4);
  EXPECT_EQ(t.integers("LEVELS", 4), (std::vector<std::int64_t>{2, 3, 0, 0, 3, 0, 0, 0}));
  EXPECT_EQ(t.integers("NLEVELS"), (std::vector<std::int64_t>{2, 1}));
  EXPECT_EQ(t.doubles("PROB"), (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(t.doubles("CONTOUR"), (std::vector<double>{0.75, 0.5}));
  EXPECT_EQ(t.integers("SPACES"), (std::vector<std::int64_t>{1, 0}));
  EXPECT_EQ(t.integers("CAND_FLAGS"), (std::vector<std::int64_t>{0, 5}));
  EXPECT_EQ(t.doubles("CURV_X")[0], 12.0);
  EXPECT_EQ(t.doubles("CURV_RADIUS")[0], 6.5);
  EXPECT_TRUE(std::isnan(t.doubles("CURV_X")[1]));
  // The lens: its row's level, number and MAG_ISO, the candidate's position and theta_E; none
  // for the second.
  EXPECT_EQ(t.integers("LENS_LEVEL"), (std::vector<std::int64_t>{1, 0}));
  EXPECT_EQ(t.integers("LENS_NUMBER"), (std::vector<std::int64_t>{7, 0}));
  EXPECT_EQ(t.doubles("LENS_X")[0], 15.5);
  EXPECT_EQ(t.doubles("LENS_MAG")[0], 19.0);
  EXPECT_EQ(t.doubles("THETA_E")[0], 1.75);
  // How theta_E was estimated (0 without a lens) and the arc-lens distance.
  EXPECT_EQ(t.integers("THETA_E_METHOD"), (std::vector<std::int64_t>{2, 0}));
  EXPECT_EQ(t.doubles("LENS_DIST")[0], 2.5);
  EXPECT_EQ(t.doubles("LENS_DELTA")[0], 2.167);
  for (const char* none : {"LENS_X", "LENS_Y", "LENS_MAG", "THETA_E", "LENS_DIST", "SEC_X"})
    EXPECT_TRUE(std::isnan(t.doubles(none)[1])) << none;

  // The summary: counts as given, the derived figures by hand.
  EXPECT_EQ(t.integer("NCANDID"), 2);
  EXPECT_EQ(t.integer("NROWSRCH"), 40);
  EXPECT_EQ(t.integer("NOBJSRCH"), 10);
  EXPECT_EQ(t.integer("NROWSEL"), 4);
  EXPECT_EQ(t.integer("SRCHPIX"), 5000);
  EXPECT_DOUBLE_EQ(t.number("SRCHAREA"), 0.01);
  EXPECT_DOUBLE_EQ(t.number("CANDDEG2"), 200.0);  // 2 / 0.01
  EXPECT_DOUBLE_EQ(t.number("REJFRAC"), 0.9);     // 1 - 4 / 40
  EXPECT_EQ(t.integer("NDARKPR"), 0);
  EXPECT_EQ(t.integer("NCOLBAND"), 0);
  EXPECT_FALSE(t.hasKeyword("COLCUTBD"));
  EXPECT_EQ(t.integer("NSPACES"), 1);
  EXPECT_EQ(t.text("SPNAME1"), "arcs");
  EXPECT_EQ(t.text("SPEXPR1"), "ARCNESS > 0.15");
  EXPECT_EQ(t.integer("SPCAND1"), 1);
  EXPECT_DOUBLE_EQ(t.number("SPDEG21"), 100.0);  // 1 / 0.01
  EXPECT_EQ(t.number("SNRMIN"), settings.snrMin);
}

TEST(CandidateTable, ColourBandColumnsFollowInOrder) {
  const Table catalog = handCatalog();
  SearchResult result = handResult();
  // [0] the measurement band, [1] g, [2] r.
  result.candidates[0].arcMags = {{21.5, 0.03}, {22.25, 0.04}, {21.0, 0.05}};
  result.candidates[0].lensMags = {{19.0, 0.01}, {20.5, 0.02}, {18.75, 0.01}};
  SearchSettings settings;
  settings.colourBands = {"g", "r"};
  settings.colourCut = ColourCut{"g", 1.5};
  const std::vector<CandidateColumnSpec> plain = candidateColumns({});
  const std::vector<CandidateColumnSpec> specs = candidateColumns(settings.colourBands);
  ASSERT_EQ(specs.size(), plain.size() + 16);
  const std::vector<std::string> perBand = {"MAG_",         "MAGERR_",        "LENS_MAG_",
                                            "LENS_MAGERR_", "ARC_COLOUR_",    "ARC_COLOURERR_",
                                            "LENS_COLOUR_", "LENS_COLOURERR_"};
  for (std::size_t b = 0; b < 2; ++b)
    for (std::size_t k = 0; k < perBand.size(); ++k)
      EXPECT_EQ(specs[plain.size() + 8 * b + k].spec.name, perBand[k] + settings.colourBands[b]);

  const FitsTable t = candidateObjectsTable(catalog, result, settings);
  EXPECT_EQ(t.doubles("MAG_g")[0], float(22.25));
  EXPECT_EQ(t.doubles("LENS_MAG_r")[0], float(18.75));
  // A colour is the band minus the measurement band, errors in quadrature.
  EXPECT_NEAR(t.doubles("ARC_COLOUR_g")[0], 0.75, 1e-6);
  EXPECT_NEAR(t.doubles("ARC_COLOURERR_g")[0], 0.05, 1e-6);  // hypot(0.03, 0.04)
  EXPECT_NEAR(t.doubles("LENS_COLOUR_r")[0], -0.25, 1e-6);
  EXPECT_NEAR(t.doubles("LENS_COLOUR_g")[0], 1.5, 1e-6);
  // The second candidate has no magnitudes and no lens.
  for (const char* none : {"MAG_g", "ARC_COLOUR_r", "LENS_MAG_g"})
    EXPECT_TRUE(std::isnan(t.doubles(none)[1])) << none;
  EXPECT_EQ(t.integer("NCOLBAND"), 2);
  EXPECT_EQ(t.text("COLBAND1"), "g");
  EXPECT_EQ(t.text("COLBAND2"), "r");
  EXPECT_EQ(t.text("COLCUTBD"), "g");
  EXPECT_EQ(t.number("COLCUTMX"), 1.5);
}

TEST(CandidateTable, EveryColumnHasAUcd) {
  const std::map<std::string, std::string> ucds = candidateColumnUcds({"g"});
  // A column copied from the catalog has the UCD its measurement declares (measure/Registry.h).
  std::map<std::string, std::string> measured;
  for (const ColumnSpec& c : allBuiltinColumns()) measured[c.name] = c.ucd;
  int copiedColumns = 0;
  for (const CandidateColumnSpec& c : candidateColumns({"g"})) {
    EXPECT_FALSE(c.spec.ucd.empty()) << c.spec.name;
    const auto m = measured.find(c.spec.name);
    if (m != measured.end() && !m->second.empty()) {
      EXPECT_EQ(c.spec.ucd, m->second) << c.spec.name;
      ++copiedColumns;
    }
  }
  EXPECT_GE(copiedColumns, 10);
  // SExtractor's UCDs for SExtractor's columns.
  EXPECT_EQ(ucds.at("X_IMAGE"), "pos.cartesian.x;pos.barycenter;instr.det;meta.main");
  EXPECT_EQ(ucds.at("ALPHA_J2000"), "pos.eq.ra;pos.barycenter;meta.main");
  EXPECT_EQ(ucds.at("MAG_g"), "phot.mag");
}

TEST(CandidateTable, AsciiHeadHasOneHeaderLinePerColumnAndOneWordPerValue) {
  const Table catalog = handCatalog();
  const SearchResult result = handResult();
  // Without the run's number of levels, LEVELS is as long as the highest level passed: 3.
  const SearchSettings settings;
  const std::vector<CandidateColumnSpec> specs = candidateColumns({}, 3);
  std::istringstream in(candidateAsciiText(catalog, result, settings));
  std::vector<std::string> header, data;
  for (std::string line; std::getline(in, line);) (line[0] == '#' ? header : data).push_back(line);
  ASSERT_EQ(header.size(), specs.size());
  ASSERT_EQ(data.size(), 2u);
  EXPECT_EQ(header[0].substr(0, 29), "#   1 NUMBER                 ");
  // A vector takes one column per element, as in SExtractor's ASCII_HEAD.
  std::vector<std::size_t> first;
  std::size_t wordCount = 0;
  for (const CandidateColumnSpec& c : specs) {
    first.push_back(wordCount);
    wordCount += std::size_t(c.spec.repeat);
  }
  for (std::size_t c = 0; c < specs.size(); ++c) {
    std::istringstream words(header[c]);
    std::string hash, index, name;
    words >> hash >> index >> name;
    EXPECT_EQ(std::stoul(index), first[c] + 1);
    EXPECT_EQ(name, specs[c].spec.name);
    const std::string unit = specs[c].spec.unit;
    if (!unit.empty()) {
      EXPECT_EQ(header[c].substr(header[c].size() - unit.size() - 2), "[" + unit + "]");
    }
  }
  // As many blank-separated words as columns; text values with blanks joined by '_', empty
  // ones as "-".
  std::vector<std::vector<std::string>> rows;
  for (const std::string& line : data) {
    std::istringstream words(line);
    rows.emplace_back();
    for (std::string w; words >> w;) rows.back().push_back(w);
    ASSERT_EQ(rows.back().size(), wordCount) << line;
  }
  auto at = [&](std::size_t r, const std::string& name, std::size_t element = 0) {
    for (std::size_t c = 0; c < specs.size(); ++c)
      if (specs[c].spec.name == name) return rows[r][first[c] + element];
    return std::string("?");
  };
  EXPECT_EQ(at(0, "NUMBER"), "1");
  EXPECT_EQ(at(1, "NUMBER"), "2");
  EXPECT_EQ(at(0, "NAME"), "OCTARC_J095950.40+021000.0");
  EXPECT_EQ(at(1, "NAME"), "-");
  EXPECT_EQ(at(0, "X_IMAGE"), "10.500");
  EXPECT_EQ(at(0, "LEVELS", 0) + at(0, "LEVELS", 1) + at(0, "LEVELS", 2), "230");
  EXPECT_EQ(at(1, "LEVELS", 0) + at(1, "LEVELS", 1) + at(1, "LEVELS", 2), "300");
  EXPECT_EQ(at(0, "LENS_NUMBER"), "7");
  EXPECT_EQ(at(1, "CAND_FLAGS"), "5");
}

}  // namespace
}  // namespace octarc
