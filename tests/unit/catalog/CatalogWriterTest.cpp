// The catalog writers against source-extractor's own FITS_LDAC, FITS_1.0 and ASCII_HEAD outputs
// for the same columns and values, plus fitsverify and astropy on the result.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "CatalogTestSupport.h"
#include "TestPaths.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/RunSummary.h"
#include "octarc/catalog/TableCatalog.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

// The columns as SExtractor 2.25 declares them (param.h): name, description, unit, type, format.
std::vector<ColumnSpec> sextractorColumns() {
  auto col = [](const char* name, const char* description, const char* unit, ColumnType type,
                const char* format, int repeat = 1) {
    return ColumnSpec{name, description, unit, "", type, format, repeat};
  };
  return {
      col("NUMBER", "Running object number", "", ColumnType::Int32, "%10d"),
      col("X_IMAGE", "Object position along x", "pixel", ColumnType::Float32, "%11.4f"),
      col("Y_IMAGE", "Object position along y", "pixel", ColumnType::Float32, "%11.4f"),
      col("X2_IMAGE", "Variance along x", "pixel**2", ColumnType::Float64, "%18.10e"),
      col("A_IMAGE", "Profile RMS along major axis", "pixel", ColumnType::Float32, "%9.3f"),
      col("THETA_IMAGE", "Position angle (CCW/x)", "deg", ColumnType::Float32, "%6.2f"),
      col("ELONGATION", "A_IMAGE/B_IMAGE", "", ColumnType::Float32, "%8.3f"),
      col("CXX_IMAGE", "Cxx object ellipse parameter", "pixel**(-2)", ColumnType::Float32,
          "%15.7e"),
      col("ISOAREA_IMAGE", "Isophotal area above Analysis threshold", "pixel**2", ColumnType::Int32,
          "%9d"),
      col("FLUX_ISO", "Isophotal flux", "count", ColumnType::Float32, "%12.7g"),
      col("MAG_ISO", "Isophotal magnitude", "mag", ColumnType::Float32, "%8.4f"),
      col("XMIN_IMAGE", "Minimum x-coordinate among detected pixels", "pixel", ColumnType::Int32,
          "%10d"),
      col("FLUX_APER", "Flux vector within fixed circular aperture(s)", "count",
          ColumnType::Float32, "%12.7g", 3),
      col("MU_MAX", "Peak surface brightness above background", "mag * arcsec**(-2)",
          ColumnType::Float32, "%8.4f"),
      col("FLAGS", "Extraction flags", "", ColumnType::Int16, "%3d"),
      col("FLUX_RADIUS", "Fraction-of-light radii", "pixel", ColumnType::Float32, "%10.3f", 2),
  };
}

const char* kParam =
    "NUMBER\nX_IMAGE\nY_IMAGE\nX2_IMAGE\nA_IMAGE\nTHETA_IMAGE\nELONGATION\nCXX_IMAGE\n"
    "ISOAREA_IMAGE\nFLUX_ISO\nMAG_ISO\nXMIN_IMAGE\nFLUX_APER(3)\nMU_MAX\nFLAGS\nFLUX_RADIUS(2)\n";

void writeText(const std::filesystem::path& file, const std::string& text) {
  std::FILE* f = std::fopen(file.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs(text.c_str(), f);
  std::fclose(f);
}

// Three rows of values for sextractorColumns(), declared here: the tests of the writer that do
// not compare with a source-extractor file need no source-extractor.
Table declaredTable() {
  Table t(sextractorColumns());
  for (int r = 0; r < 3; ++r) {
    double* row = t.appendRow();
    const double values[] = {double(r + 1),      // NUMBER
                             10.5 + r,           // X_IMAGE
                             20.25 - r,          // Y_IMAGE
                             0.125 * (r + 1),    // X2_IMAGE
                             1.5,                // A_IMAGE
                             -30.0 + 10 * r,     // THETA_IMAGE
                             1.25,               // ELONGATION
                             0.5,                // CXX_IMAGE
                             6.0 + r,            // ISOAREA_IMAGE
                             100.0 * (r + 1),    // FLUX_ISO
                             20.0 - r,           // MAG_ISO
                             double(3 * r + 1),  // XMIN_IMAGE
                             1.0,
                             2.0,
                             3.0 + r,                 // FLUX_APER(3)
                             21.5,                    // MU_MAX
                             double(r == 2 ? 8 : 0),  // FLAGS
                             0.75,
                             1.75};  // FLUX_RADIUS(2)
    std::copy(std::begin(values), std::end(values), row);
  }
  return t;
}

// The LDAC_IMHEAD of a run on the small image: its 8 header cards and SExtractor's 46 run cards.
CatalogPart declaredPart(const Table& table) {
  CatalogPart part;
  const auto card = [](std::string text) {
    text.resize(80, ' ');
    return text;
  };
  part.imageHeader.cards = {
      card("SIMPLE  =                    T / file does conform to FITS standard"),
      card("BITPIX  =                  -32 / number of bits per data pixel"),
      card("NAXIS   =                    2 / number of data axes"),
      card("NAXIS1  =                   64 / length of data axis 1"),
      card("NAXIS2  =                   48 / length of data axis 2"),
      card("EXTEND  =                    T / FITS dataset may contain extensions"),
      card("GAIN    =                   2."),
      card("OBJECT  = 'test    '"),
  };
  RunSummary run;
  run.fitsFile = "small.fits";
  run.version = "octarc test";
  run.date = "01/12/2026";
  run.time = "12:00:00";
  run.detections = 3;
  run.finalObjects = 3;
  run.parameters = 16;
  part.runCards = sexRunCards(run);
  part.objects = &table;
  return part;
}

// The writer on declared values; needs no other program.
class CatalogWriter : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratchDir();
    table_ = declaredTable();
    part_ = declaredPart(table_);
  }

  std::filesystem::path dir_;
  Table table_;
  CatalogPart part_;
};

// The writer against source-extractor's own files: the table holds the values source-extractor
// measured on the small image (declared by hand with SExtractor's column metadata) and the part
// its LDAC_IMHEAD cards; only these tests need source-extractor.
class CatalogWriterVsSExtractor : public CatalogWriter {
 protected:
  void SetUp() override {
    CatalogWriter::SetUp();
    if (!test::haveProgram("source-extractor"))
      OCTARC_SKIP_MISSING() << "source-extractor not installed";
    test::writeSmallImage(dir_ / "small.fits");
    writeText(dir_ / "t.param", kParam);
    ldac_ = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "se.ldac");
    table_ = test::readTable(ldac_, 3, sextractorColumns());
    ASSERT_EQ(table_.rows(), 3);
    // The image header and the run cards exactly as in source-extractor's LDAC_IMHEAD.
    const std::vector<std::string> cell = test::imheadCards(ldac_, 2);
    part_.imageHeader.cards.clear();
    part_.runCards.clear();
    for (std::size_t i = 0; i + 1 < cell.size(); ++i) {
      if (i < 8) {  // SIMPLE..OBJECT
        part_.imageHeader.cards.push_back(cell[i]);
      } else {
        part_.runCards.push_back(cell[i]);
      }
    }
    part_.objects = &table_;
  }

  std::filesystem::path ldac_;
};

// Compares two table headers: the same keywords in the same order; TTYPE with its comment,
// TFORM, TUNIT, TDISP, TDIM, EXTNAME, NAXISn, TFIELDS by value.
void expectSameTableHeader(const std::vector<test::Card>& ours,
                           const std::vector<test::Card>& theirs) {
  ASSERT_EQ(ours.size(), theirs.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(ours[i].key, theirs[i].key) << i;
    EXPECT_EQ(ours[i].value, theirs[i].value) << theirs[i].image;
    const std::string& key = theirs[i].key;
    if (key.rfind("TTYPE", 0) == 0 || key == "EXTNAME" || key.rfind("NAXIS", 0) == 0 ||
        key == "XTENSION" || key == "TFIELDS" || key == "PCOUNT" || key == "GCOUNT") {
      EXPECT_EQ(ours[i].comment, theirs[i].comment) << theirs[i].image;
    }
    if (key.rfind("TTYPE", 0) == 0 || key.rfind("TFORM", 0) == 0 || key.rfind("TUNIT", 0) == 0 ||
        key.rfind("TDISP", 0) == 0 || key.rfind("TDIM", 0) == 0 || key == "EXTNAME") {
      EXPECT_EQ(ours[i].image, theirs[i].image);  // these cards byte for byte
    }
  }
}

TEST_F(CatalogWriterVsSExtractor, LdacMatchesSourceExtractor) {
  const auto ours = dir_ / "ours.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part_});
  ASSERT_EQ(test::hduCount(ours), 3);
  // Primary: SIMPLE, BITPIX, NAXIS, EXTEND with the same values and comments.
  const auto p1 = test::headerCards(ours, 1);
  const auto p2 = test::headerCards(ldac_, 1);
  ASSERT_EQ(p1.size(), p2.size());
  for (std::size_t i = 0; i < p1.size(); ++i) {
    EXPECT_EQ(p1[i].key, p2[i].key);
    EXPECT_EQ(p1[i].value, p2[i].value);
    EXPECT_EQ(p1[i].comment, p2[i].comment);
  }
  expectSameTableHeader(test::headerCards(ours, 2), test::headerCards(ldac_, 2));
  expectSameTableHeader(test::headerCards(ours, 3), test::headerCards(ldac_, 3));
  // The data: the LDAC_IMHEAD cell and every object row byte for byte.
  EXPECT_EQ(test::tableBytes(ours, 2), test::tableBytes(ldac_, 2));
  EXPECT_EQ(test::tableBytes(ours, 3), test::tableBytes(ldac_, 3));
}

// Only the warnings LDAC's layout gives (source-extractor's files too, next test): two per
// LDAC_IMHEAD for the blank in 'Field Header Card', one per repeated extension name.
TEST_F(CatalogWriter, LdacPassesFitsverify) {
  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  const auto one = dir_ / "one.ldac", two = dir_ / "two.ldac";
  writeCatalog(one.string(), CatalogType::FitsLdac, {part_});
  writeCatalog(two.string(), CatalogType::FitsLdac, {part_, part_});
  const test::FitsverifyReport a = test::fitsverify(one), b = test::fitsverify(two);
  EXPECT_EQ(a.errors, 0) << a.text;
  EXPECT_EQ(a.warnings, 2) << a.text;
  EXPECT_EQ(b.errors, 0) << b.text;
  EXPECT_EQ(b.warnings, 2 + 2 + 2) << b.text;
}

TEST_F(CatalogWriterVsSExtractor, FitsverifyFindsWhatItFindsInSourceExtractorsLdac) {
  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  const auto ours = dir_ / "ours.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part_});
  const test::FitsverifyReport mine = test::fitsverify(ours), theirs = test::fitsverify(ldac_);
  EXPECT_EQ(theirs.errors, 0) << theirs.text;
  EXPECT_EQ(theirs.warnings, 2) << theirs.text;
  EXPECT_EQ(mine.errors, theirs.errors) << mine.text;
  EXPECT_EQ(mine.warnings, theirs.warnings) << mine.text;
}

TEST_F(CatalogWriter, AstropyReadsColumnsUnitsAndDescriptions) {
  const auto ours = dir_ / "ours.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part_});
  std::string out;
  const std::string script = std::string(OCTARC_SOURCE_DIR) + "/tests/unit/catalog/read_catalog.py";
  ASSERT_EQ(
      test::runCommand("/usr/bin/python3 '" + script + "' '" + ours.string() + "' 2>&1", &out), 0)
      << out;
  EXPECT_NE(out.find("IMHEAD 1 55 SIMPLE  =                    T"), std::string::npos) << out;
  EXPECT_NE(out.find("TABLE 2 LDAC_OBJECTS 3\n"), std::string::npos) << out;
  for (const ColumnSpec& c : sextractorColumns()) {
    const std::string line = "COLUMN 2 " + c.name + "|" + c.unit + "|" +
                             tdispFromPrintf(c.printfFormat) + "|" + c.description + "|";
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
  }
  // astropy parses every unit (SExtractor's "pixel**(-2)" and "mag * arcsec**(-2)" included).
  EXPECT_EQ(out.find("|False\n"), std::string::npos) << out;
  EXPECT_NE(out.find("COLUMN 2 NUMBER||I10|Running object number|1|True\n"), std::string::npos)
      << out;
}

TEST_F(CatalogWriterVsSExtractor, Fits10MatchesSourceExtractor) {
  const auto theirs =
      test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_1.0", "se.fits");
  std::vector<std::string> primary;
  const auto theirPrimary = test::headerCards(theirs, 1);
  for (std::size_t i = 4; i < theirPrimary.size(); ++i) primary.push_back(theirPrimary[i].image);
  const auto ours = dir_ / "ours.fits";
  writeCatalog(ours.string(), CatalogType::Fits10, {part_}, primary);
  ASSERT_EQ(test::hduCount(ours), 2);
  const auto ourPrimary = test::headerCards(ours, 1);
  ASSERT_EQ(ourPrimary.size(), theirPrimary.size());
  for (std::size_t i = 0; i < ourPrimary.size(); ++i) {
    EXPECT_EQ(ourPrimary[i].key, theirPrimary[i].key);
    EXPECT_EQ(ourPrimary[i].value, theirPrimary[i].value);
  }
  expectSameTableHeader(test::headerCards(ours, 2), test::headerCards(theirs, 2));
  EXPECT_EQ(test::tableBytes(ours, 2), test::tableBytes(theirs, 2));
}

TEST_F(CatalogWriter, Fits10JoinsThePartsInOneTable) {
  const auto ours = dir_ / "ours.fits";
  writeCatalog(ours.string(), CatalogType::Fits10, {part_, part_});
  ASSERT_EQ(test::hduCount(ours), 2);
  const std::vector<double> numbers = test::columnValues(ours, 2, "NUMBER");
  EXPECT_EQ(numbers, (std::vector<double>{1, 2, 3, 1, 2, 3}));
}

TEST_F(CatalogWriterVsSExtractor, AsciiHeadMatchesSourceExtractorByteForByte) {
  const auto theirs =
      test::runSourceExtractor(dir_, "small.fits", "t.param", "ASCII_HEAD", "se.txt");
  const auto ours = dir_ / "ours.txt";
  writeCatalog(ours.string(), CatalogType::AsciiHead, {part_});
  EXPECT_EQ(test::readFile(ours), test::readFile(theirs));
}

// The header lines without source-extractor: a vector column takes n columns.
TEST_F(CatalogWriter, AsciiHeadNumbersVectorElementsAsColumns) {
  const auto ours = dir_ / "ours.txt";
  writeCatalog(ours.string(), CatalogType::AsciiHead, {part_});
  const std::string text = test::readFile(ours);
  EXPECT_NE(text.find("\n#  13 FLUX_APER "), std::string::npos);
  EXPECT_NE(text.find("\n#  16 MU_MAX "), std::string::npos);
  EXPECT_NE(text.find("\n#  18 FLUX_RADIUS "), std::string::npos);
  EXPECT_EQ(
      text.substr(0, 88),
      "#   1 NUMBER                 Running object number                                     \n");
}

TEST_F(CatalogWriterVsSExtractor, AsciiMatchesSourceExtractorByteForByte) {
  const auto theirs = test::runSourceExtractor(dir_, "small.fits", "t.param", "ASCII", "se.txt");
  const auto ours = dir_ / "ours.txt";
  writeCatalog(ours.string(), CatalogType::Ascii, {part_});
  EXPECT_EQ(test::readFile(ours), test::readFile(theirs));
}

// ASCII_VOTABLE: FIELDs with the VO units and UCDs, vectors as arraysize, XML escaped, NaN as
// VOTable's "NaN", and the values astropy reads back.
TEST_F(CatalogWriter, VotableDeclaresFieldsAndReadsBackInAstropy) {
  std::vector<ColumnSpec> columns = sextractorColumns();
  columns[6].description = "A_IMAGE/B_IMAGE & \"a<b\"";
  columns[1].ucd = "pos.cartesian.x;instr.det";
  Table table(columns);
  for (std::int64_t r = 0; r < table_.rows(); ++r) {
    double* row = table.appendRow();
    for (int c = 0, k = 0; c < table_.columnCount(); ++c) {
      for (int e = 0; e < table_.columns()[std::size_t(c)].repeat; ++e) {
        row[k++] = table_.value(r, c, e);
      }
    }
  }
  table.setValue(1, table.findColumn("MU_MAX"), std::nan(""));
  CatalogPart part = part_;
  part.objects = &table;
  const auto ours = dir_ / "ours.xml";
  writeCatalog(ours.string(), CatalogType::AsciiVotable, {part});
  const std::string text = test::readFile(ours);
  EXPECT_NE(text.find("<VOTABLE version=\"1.3\""), std::string::npos);
  EXPECT_NE(text.find("<FIELD name=\"X_IMAGE\" datatype=\"float\" unit=\"pix\" "
                      "ucd=\"pos.cartesian.x;instr.det\">"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("<FIELD name=\"FLUX_APER\" datatype=\"float\" arraysize=\"3\" unit=\"ct\">"),
            std::string::npos);
  EXPECT_NE(text.find("<DESCRIPTION>A_IMAGE/B_IMAGE &amp; &quot;a&lt;b&quot;</DESCRIPTION>"),
            std::string::npos);
  // Row 1: X_IMAGE 11.5, FLUX_APER (1, 2, 4), MU_MAX undefined.
  EXPECT_NE(text.find("<TD>11.5</TD>"), std::string::npos);
  EXPECT_NE(text.find("<TD>1 2 4</TD><TD>NaN</TD>"), std::string::npos) << text;
  EXPECT_EQ(text.find(".tmp"), std::string::npos);
  std::string out;
  const std::string script =
      "from astropy.io.votable import parse_single_table\n"
      "t = parse_single_table('" +
      ours.string() +
      "').to_table()\n"
      "print(t['X_IMAGE'][1], t['FLUX_APER'][1].tolist(), t['MU_MAX'][1], t['MU_MAX'][0],\n"
      "      t['ISOAREA_IMAGE'].dtype, t['X2_IMAGE'][2], t['ELONGATION'].description)\n"
      "p = {q.name: q.value for q in parse_single_table('" +
      ours.string() +
      "').params}\n"
      "print(p['SEXNDET'], p['SEXNPARA'])\n";
  ASSERT_EQ(test::runCommand("/usr/bin/python3 -W ignore -c \"" + script + "\" 2>&1", &out), 0)
      << out;
  EXPECT_EQ(out, "11.5 [1.0, 2.0, 4.0] -- 21.5 int32 0.375 A_IMAGE/B_IMAGE & \"a<b\"\n3 16\n");
}

// Several image extensions: one table of every row, each extension's cards in its GROUP; an
// undefined card value is a NaN PARAM.
TEST_F(CatalogWriter, VotableGroupsTheCardsOfEachExtension) {
  CatalogPart second = part_;
  second.runCards.push_back(std::string("OCTUNDEF=").append(71, ' '));
  const auto out = dir_ / "two.xml";
  writeCatalog(out.string(), CatalogType::AsciiVotable, {part_, second});
  const std::string text = test::readFile(out);
  EXPECT_NE(text.find("<GROUP name=\"EXTENSION_1\">"), std::string::npos);
  EXPECT_NE(text.find("<GROUP name=\"EXTENSION_2\">"), std::string::npos);
  EXPECT_NE(text.find("<PARAM name=\"OCTUNDEF\" datatype=\"double\" ucd=\"obs.param\" "
                      "value=\"NaN\"/>"),
            std::string::npos)
      << text;
  std::size_t rows = 0;
  for (std::size_t at = text.find("<TR>"); at != std::string::npos; at = text.find("<TR>", at + 1))
    ++rows;
  EXPECT_EQ(rows, 6u);
}

// A table with text and vector columns (the candidates'), in the text catalog types.
FitsTable textAndVectorTable() {
  FitsTable t;
  t.name = "LDAC_OBJECTS";
  t.keywords = {FitsKeyword::integer("NCANDID", 2, "candidates"),
                FitsKeyword::real("SRCHAREA", std::nan(""), "[deg2] searched area"),
                FitsKeyword::text("SELMETH", "GRID")};
  t.columns = {
      {"NAME", "Designation", "", "", 0, std::vector<std::string>{"A <1> & B", ""}, "", ""},
      {"LEVELS", "Levels passed", "", "", 3, std::vector<std::int16_t>{2, 3, 0, 5, 0, 0}, "", ""},
      {"X_IMAGE", "x", "pixel", "F8.3", 1, std::vector<float>{10.5f, std::nanf("")}, "", ""},
  };
  return t;
}

TEST_F(CatalogWriter, TableCatalogAsciiHeadNumbersVectorElementsAndJoinsWords) {
  const auto out = dir_ / "t.cat";
  writeTableCatalog(out.string(), CatalogType::AsciiHead, textAndVectorTable(), FitsTable());
  EXPECT_EQ(
      test::readFile(out),
      "#   1 NAME                   Designation                                               \n"
      "#   2 LEVELS                 Levels passed                                             \n"
      "#   5 X_IMAGE                x                                                          "
      "[pixel]\n"
      "A_<1>_&_B 2 3 0   10.500\n"
      "- 5 0 0      nan\n");
}

TEST_F(CatalogWriter, TableCatalogVotableEscapesTextAndDeclaresVectors) {
  const auto out = dir_ / "t.xml";
  writeTableCatalog(out.string(), CatalogType::AsciiVotable, textAndVectorTable(), FitsTable(),
                    {{"NAME", "meta.id;meta.main"}, {"LEVELS", "meta.id.part"}});
  const std::string text = test::readFile(out);
  EXPECT_NE(text.find("<PARAM name=\"SRCHAREA\" datatype=\"double\" value=\"NaN\">"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("<FIELD name=\"NAME\" datatype=\"char\" arraysize=\"*\" "
                      "ucd=\"meta.id;meta.main\">"),
            std::string::npos);
  EXPECT_NE(text.find("<FIELD name=\"LEVELS\" datatype=\"short\" arraysize=\"3\" "
                      "ucd=\"meta.id.part\">"),
            std::string::npos);
  EXPECT_NE(text.find("<FIELD name=\"X_IMAGE\" datatype=\"float\" unit=\"pix\">"),
            std::string::npos);
  EXPECT_NE(text.find("<TR><TD>A &lt;1&gt; &amp; B</TD><TD>2 3 0</TD><TD>10.5</TD></TR>"),
            std::string::npos);
  EXPECT_NE(text.find("<TR><TD></TD><TD>5 0 0</TD><TD>NaN</TD></TR>"), std::string::npos);
}

TEST_F(CatalogWriter, TableCatalogFits10IsOneObjectsTable) {
  const auto out = dir_ / "t.fits";
  writeTableCatalog(out.string(), CatalogType::Fits10, textAndVectorTable(), FitsTable());
  EXPECT_EQ(listFitsTables(out.string()), (std::vector<std::string>{"OBJECTS"}));
  const FitsTable back = readFitsTable(out.string(), "OBJECTS");
  EXPECT_EQ(back.integers("LEVELS", 3), (std::vector<std::int64_t>{2, 3, 0, 5, 0, 0}));
  EXPECT_EQ(back.integer("NCANDID"), 2);
  EXPECT_THROW(writeTableCatalog((dir_ / "n").string(), CatalogType::None, textAndVectorTable(),
                                 FitsTable()),
               ConfigError);
}

TEST_F(CatalogWriter, EmptyTableGivesAValidCatalog) {
  Table empty(sextractorColumns());
  CatalogPart part = part_;
  part.objects = &empty;
  const auto ours = dir_ / "empty.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part});
  std::map<std::string, std::string> header;
  for (const auto& c : test::headerCards(ours, 3)) header[c.key] = c.value;
  EXPECT_EQ(header["NAXIS2"], "0");
  EXPECT_EQ(header["NAXIS1"], "78");  // 4+4+4+8+4+4+4+4+4+4+4+4+12+4+2+8 bytes per row
  EXPECT_EQ(header["TFIELDS"], "16");
  const auto text = dir_ / "empty.txt";
  writeCatalog(text.string(), CatalogType::Ascii, {part});
  EXPECT_EQ(test::readFile(text), "");
  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  const test::FitsverifyReport report = test::fitsverify(ours);
  EXPECT_EQ(report.errors, 0) << report.text;
  EXPECT_EQ(report.warnings, 2) << report.text;
}

// A catalog with every octarc column has a header of several FITS blocks; growing it used to
// fail inside cfitsio ("tried to move past end of file") once it needed a new block.
TEST_F(CatalogWriter, WideTableHeaderSpansSeveralBlocks) {
  std::vector<ColumnSpec> columns;
  for (int i = 1; i <= 120; ++i) {
    columns.push_back({"COL" + std::to_string(i), "Column number " + std::to_string(i), "pixel",
                       "src", ColumnType::Float32, "%11.4f", 1});
  }
  Table wide(columns);
  for (int r = 0; r < 3; ++r) {
    double* row = wide.appendRow();
    for (int c = 0; c < wide.rowWidth(); ++c) row[c] = r * 1000 + c;
  }
  CatalogPart part = part_;
  part.objects = &wide;
  const auto ours = dir_ / "wide.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part});
  std::map<std::string, std::string> header;
  for (const auto& c : test::headerCards(ours, 3)) header[c.key] = c.value;
  EXPECT_EQ(header["TFIELDS"], "120");
  EXPECT_EQ(header["TTYPE120"], "'COL120  '");
  EXPECT_EQ(header["TDISP120"], "'F11.4   '");
  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  const test::FitsverifyReport report = test::fitsverify(ours);
  EXPECT_EQ(report.errors, 0) << report.text;
  EXPECT_EQ(report.warnings, 2) << report.text;
}

TEST_F(CatalogWriter, DirectoryNamesAreNotTakenForCfitsioSyntax) {
  std::filesystem::create_directories(dir_ / "run[1](a)");
  const auto ours = dir_ / "run[1](a)" / "out.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part_});
  ASSERT_TRUE(std::filesystem::exists(ours));
  std::filesystem::copy_file(ours, dir_ / "copy.ldac");
  const auto plain = dir_ / "plain.ldac";
  writeCatalog(plain.string(), CatalogType::FitsLdac, {part_});
  EXPECT_EQ(test::readFile(dir_ / "copy.ldac"), test::readFile(plain));
}

TEST_F(CatalogWriter, NoneWritesNothing) {
  const auto ours = dir_ / "none.cat";
  writeCatalog(ours.string(), CatalogType::None, {part_});
  EXPECT_FALSE(std::filesystem::exists(ours));
}

TEST_F(CatalogWriter, UnwritableDirectoryIsAOneLineIoError) {
  const auto ours = dir_ / "missing-dir" / "out.ldac";
  for (CatalogType type : {CatalogType::FitsLdac, CatalogType::AsciiHead}) {
    try {
      writeCatalog(ours.string(), type, {part_});
      ADD_FAILURE() << "no error";
    } catch (const IoError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(ours.string()), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(ours));
}

TEST_F(CatalogWriter, ReplacesAnExistingFileAndLeavesNoTemporaryFile) {
  const auto ours = dir_ / "out.ldac";
  writeText(ours, "old content");
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part_});
  const auto fresh = dir_ / "fresh.ldac";
  writeCatalog(fresh.string(), CatalogType::FitsLdac, {part_});
  EXPECT_EQ(test::readFile(ours), test::readFile(fresh));
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(CatalogWriter, PartsWithDifferentColumnsAreRejected) {
  std::vector<ColumnSpec> other = sextractorColumns();
  other.pop_back();
  Table small(other);
  CatalogPart second = part_;
  second.objects = &small;
  EXPECT_THROW(writeCatalog((dir_ / "x.ldac").string(), CatalogType::FitsLdac, {part_, second}),
               ConfigError);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.ldac"));
}

// Two parts give two IMHEAD/OBJECTS pairs, each with its own header and rows; NaN survives.
TEST_F(CatalogWriter, LdacWritesOnePairPerPart) {
  Table second(sextractorColumns());
  double* row = second.appendRow();
  row[0] = 1;
  row[1] = std::nan("");
  CatalogPart part2 = part_;
  part2.objects = &second;
  part2.imageHeader.cards.resize(3);
  const auto ours = dir_ / "two.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {part_, part2});
  ASSERT_EQ(test::hduCount(ours), 5);
  EXPECT_EQ(test::imheadCards(ours, 4).size(), 3u + 46u + 1u);  // 3 image cards, 46 run cards, END
  std::map<std::string, std::string> header;
  for (const auto& c : test::headerCards(ours, 4)) header[c.key] = c.value;
  EXPECT_EQ(header["TDIM1"], "'(80, 50)'");
  EXPECT_EQ(header["TFORM1"], "'4000A   '");
  EXPECT_EQ(test::columnValues(ours, 5, "NUMBER"), std::vector<double>{1});
  EXPECT_TRUE(std::isnan(test::columnValues(ours, 5, "X_IMAGE")[0]));
}

}  // namespace
}  // namespace octarc
