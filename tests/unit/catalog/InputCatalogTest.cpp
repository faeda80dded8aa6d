// Reading source-extractor catalogs and appending columns to them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "CatalogTestSupport.h"
#include "FitsHeaders.h"
#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/catalog/AppendedCatalog.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {
namespace {

const char* kInputParam =
    "NUMBER\nX_IMAGE\nY_IMAGE\nISOAREA_IMAGE\nFLUX_ISO\nFLUX_APER(3)\nFLAGS\n";

std::vector<ColumnSpec> octopoleColumns() {
  return {
      ColumnSpec{"ARCNESS", "Octopole arcness", "", "src.morph", ColumnType::Float32, "%8.4f", 1},
      ColumnSpec{"I_AAB_IMAGE", "Third moment along a, a, b", "pixel**3", "src.morph",
                 ColumnType::Float64, "%18.10e", 1},
      ColumnSpec{"ARC_SIDE", "Sign of I_AAB", "", "src.morph", ColumnType::Int16, "%3d", 1},
      ColumnSpec{"SKEWS", "Skewness along a and b", "", "src.morph", ColumnType::Float32, "%+8.4f",
                 2},
  };
}

// New column values that differ per row: row r gets r + 0.25 etc.
Table octopoleTable(std::int64_t rows) {
  Table t(octopoleColumns());
  for (std::int64_t r = 0; r < rows; ++r) {
    double* row = t.appendRow();
    row[0] = double(r) + 0.25;
    row[1] = 1e-3 * double(r + 1);
    row[2] = r % 2 == 0 ? 1 : -1;
    row[3] = double(r);
    row[4] = std::nan("");
  }
  return t;
}

class InputCatalog : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratchDir();
    test::writeSmallImage(dir_ / "small.fits");
    test::writeTwoExtensionImage(dir_ / "mef.fits");
    std::FILE* f = std::fopen((dir_ / "t.param").c_str(), "w");
    std::fputs(kInputParam, f);
    std::fclose(f);
  }

  std::filesystem::path dir_;
};

TEST_F(InputCatalog, ReadsSourceExtractorLdac) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::vector<InputCatalogPart> parts = readInputCatalog(cat.string());
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].objectsHdu, 3);
  EXPECT_EQ(parts[0].numbers, (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(parts[0].columnNames,
            (std::vector<std::string>{"NUMBER", "X_IMAGE", "Y_IMAGE", "ISOAREA_IMAGE", "FLUX_ISO",
                                      "FLUX_APER", "FLAGS"}));
  // 8 image cards and 46 SEx* cards, END not included.
  ASSERT_EQ(parts[0].imageHeader.cards.size(), 54u);
  EXPECT_EQ(parts[0].imageHeader.cards[0].substr(0, 30), "SIMPLE  =                    T");
  EXPECT_EQ(parts[0].imageHeader.cards[6].substr(0, 8), "GAIN    ");
  EXPECT_EQ(parts[0].imageHeader.cards[53].substr(0, 8), "SEXDWSCL");
  // The NUMBERs are the ones of the rows: the block (ISOAREA 6) is one of them.
  const std::vector<double> area = test::columnValues(cat, 3, "ISOAREA_IMAGE");
  EXPECT_EQ(area.size(), 3u);
}

TEST_F(InputCatalog, ReadsSourceExtractorFits10) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_1.0", "c.fits");
  const std::vector<InputCatalogPart> parts = readInputCatalog(cat.string());
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].objectsHdu, 2);
  EXPECT_EQ(parts[0].numbers, (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_TRUE(parts[0].imageHeader.cards.empty());
}

TEST_F(InputCatalog, ReadsOnePartPerExtension) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "mef.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::vector<InputCatalogPart> parts = readInputCatalog(cat.string());
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].objectsHdu, 3);
  EXPECT_EQ(parts[1].objectsHdu, 5);
  EXPECT_EQ(parts[0].numbers, (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(parts[1].numbers, (std::vector<std::int64_t>{1, 2}));  // NUMBER restarts at 1
  EXPECT_EQ(parts[1].imageHeader.cards[0].substr(0, 20), "XTENSION= 'IMAGE   '");
}

TEST_F(InputCatalog, AppendKeepsEverythingAndAddsColumns) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "mef.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::string before = test::readFile(cat);
  const Table add1 = octopoleTable(3);
  const Table add2 = octopoleTable(2);
  const auto out = dir_ / "out.ldac";
  writeAppendedCatalog(cat.string(), out.string(), {&add1, &add2});
  EXPECT_EQ(test::readFile(cat), before);  // input untouched
  ASSERT_EQ(test::hduCount(out), 5);

  // Primary and LDAC_IMHEAD HDUs: every card and every byte of data unchanged.
  for (int hdu : {1, 2, 4}) {
    const auto a = test::headerCards(cat, hdu);
    const auto b = test::headerCards(out, hdu);
    ASSERT_EQ(a.size(), b.size()) << hdu;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].image, b[i].image);
    if (hdu != 1) {
      EXPECT_EQ(test::tableBytes(cat, hdu), test::tableBytes(out, hdu));
    }
  }
  const std::vector<std::string> original = {"NUMBER",   "X_IMAGE",   "Y_IMAGE", "ISOAREA_IMAGE",
                                             "FLUX_ISO", "FLUX_APER", "FLAGS"};
  for (int hdu : {3, 5}) {
    const Table& added = hdu == 3 ? add1 : add2;
    // Original columns: same values (exact, compared bit for bit) and same header cards.
    for (const std::string& name : original) {
      const std::vector<double> a = test::columnValues(cat, hdu, name);
      const std::vector<double> b = test::columnValues(out, hdu, name);
      ASSERT_EQ(a.size(), b.size());
      EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << name;
    }
    const auto a = test::headerCards(cat, hdu);
    const auto b = test::headerCards(out, hdu);
    ASSERT_EQ(b.size(), a.size() + 4 + 4 + 1 + 4);  // TTYPE, TFORM each; 1 TUNIT; 4 TDISP
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i].key == "NAXIS1" || a[i].key == "TFIELDS") continue;
      EXPECT_EQ(a[i].image, b[i].image);  // original cards in place, new ones after them
    }
    // New columns: values, types, units, display formats and descriptions.
    std::map<std::string, std::string> header;
    std::map<std::string, std::string> comments;
    for (const auto& c : b) {
      header[c.key] = c.value;
      comments[c.key] = c.comment;
    }
    EXPECT_EQ(header["TFIELDS"], "11");
    EXPECT_EQ(header["TTYPE8"], "'ARCNESS '");
    EXPECT_EQ(comments["TTYPE8"], "Octopole arcness");
    EXPECT_EQ(header["TFORM8"], "'1E      '");
    EXPECT_EQ(header["TDISP8"], "'F8.4    '");
    EXPECT_EQ(header.count("TUNIT8"), 0u);
    EXPECT_EQ(header["TFORM9"], "'1D      '");
    EXPECT_EQ(header["TUNIT9"], "'pixel**3'");
    EXPECT_EQ(header["TFORM10"], "'1I      '");
    EXPECT_EQ(header["TFORM11"], "'2E      '");
    EXPECT_EQ(header["TDISP11"], "'F8.4    '");
    const std::vector<double> arcness = test::columnValues(out, hdu, "ARCNESS");
    const std::vector<double> iaab = test::columnValues(out, hdu, "I_AAB_IMAGE");
    const std::vector<double> side = test::columnValues(out, hdu, "ARC_SIDE");
    const std::vector<double> skews = test::columnValues(out, hdu, "SKEWS");
    ASSERT_EQ(arcness.size(), std::size_t(added.rows()));
    for (std::int64_t r = 0; r < added.rows(); ++r) {
      EXPECT_EQ(arcness[std::size_t(r)], double(r) + 0.25);
      EXPECT_EQ(iaab[std::size_t(r)], 1e-3 * double(r + 1));
      EXPECT_EQ(side[std::size_t(r)], r % 2 == 0 ? 1.0 : -1.0);
      EXPECT_EQ(skews[std::size_t(2 * r)], double(r));
      EXPECT_TRUE(std::isnan(skews[std::size_t(2 * r + 1)]));
    }
  }
  // The result is still a catalog readInputCatalog accepts, with the new column names.
  const auto parts = readInputCatalog(out.string());
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[1].columnNames.back(), "SKEWS");
  EXPECT_EQ(parts[1].numbers, (std::vector<std::int64_t>{1, 2}));
  // astropy sees the new columns with their units and descriptions.
  std::string astropy;
  const std::string script = std::string(OCTARC_SOURCE_DIR) + "/tests/unit/catalog/read_catalog.py";
  ASSERT_EQ(
      test::runCommand("/usr/bin/python3 '" + script + "' '" + out.string() + "' 2>&1", &astropy),
      0)
      << astropy;
  EXPECT_NE(astropy.find("COLUMN 4 I_AAB_IMAGE|pixel**3|E18.10|Third moment along a, a, b|0.001|"
                         "True\n"),
            std::string::npos)
      << astropy;
  EXPECT_NE(astropy.find("COLUMN 4 ARCNESS||F8.4|Octopole arcness|0.25|True\n"), std::string::npos)
      << astropy;
  EXPECT_NE(astropy.find("IMHEAD 3 "), std::string::npos) << astropy;
  OCTARC_REQUIRE_PROGRAM("fitsverify");
  const test::FitsverifyReport report = test::fitsverify(out);
  EXPECT_EQ(report.errors, 0) << report.text;
}

TEST_F(InputCatalog, AppendsToFits10InPlace) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_1.0", "c.fits");
  const std::vector<double> flux = test::columnValues(cat, 2, "FLUX_ISO");
  const Table add = octopoleTable(3);
  writeAppendedCatalog(cat.string(), cat.string(), {&add});
  EXPECT_EQ(test::columnValues(cat, 2, "FLUX_ISO"), flux);
  EXPECT_EQ(test::columnValues(cat, 2, "ARCNESS"), (std::vector<double>{0.25, 1.25, 2.25}));
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(InputCatalog, FailureHalfwayLeavesNoOutputAndTheInputUntouched) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "mef.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::string before = test::readFile(cat);
  const Table good = octopoleTable(3);
  const Table wrongRows = octopoleTable(3);  // the second table has 2 rows
  const auto out = dir_ / "out.ldac";
  try {
    writeAppendedCatalog(cat.string(), out.string(), {&good, &wrongRows});
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(cat.string()), std::string::npos) << what;
    EXPECT_NE(what.find("has 2 rows"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  // Same in place: the input keeps every byte.
  EXPECT_THROW(writeAppendedCatalog(cat.string(), cat.string(), {&good, &wrongRows}), IoError);
  EXPECT_EQ(test::readFile(cat), before);
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
  // Wrong number of tables.
  EXPECT_THROW(writeAppendedCatalog(cat.string(), out.string(), {&good}), IoError);
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(InputCatalog, ExistingColumnNameIsAConfigError) {
  OCTARC_REQUIRE_PROGRAM("source-extractor");
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::string before = test::readFile(cat);
  Table clash(
      {ColumnSpec{"FLUX_ISO", "Isophotal flux", "count", "", ColumnType::Float32, "%12.7g", 1}});
  for (int r = 0; r < 3; ++r) clash.appendRow();
  try {
    writeAppendedCatalog(cat.string(), cat.string(), {&clash});
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("FLUX_ISO"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::readFile(cat), before);
}

TEST_F(InputCatalog, CatalogWithoutNumberIsAnIoError) {
  Table noNumber({ColumnSpec{"X_IMAGE", "Object position along x", "pixel", "", ColumnType::Float32,
                             "%11.4f", 1}});
  noNumber.appendRow()[0] = 3.0;
  const auto file = dir_ / "nonumber.ldac";
  CatalogPart part;
  part.objects = &noNumber;
  writeCatalog(file.string(), CatalogType::FitsLdac, {part});
  try {
    readInputCatalog(file.string());
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    EXPECT_NE(what.find("no NUMBER column"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  const Table add = octopoleTable(1);
  EXPECT_THROW(writeAppendedCatalog(file.string(), (dir_ / "o.ldac").string(), {&add}), IoError);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "o.ldac"));
}

TEST_F(InputCatalog, NotACatalogIsAnIoError) {
  // An image, not a catalog.
  try {
    readInputCatalog((dir_ / "small.fits").string());
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("no LDAC_OBJECTS or OBJECTS table"), std::string::npos)
        << e.what();
  }
  // Not FITS at all, and missing.
  std::FILE* f = std::fopen((dir_ / "text.cat").c_str(), "w");
  std::fputs("# 1 NUMBER\n1\n", f);
  std::fclose(f);
  EXPECT_THROW(readInputCatalog((dir_ / "text.cat").string()), IoError);
  EXPECT_THROW(readInputCatalog((dir_ / "missing.ldac").string()), IoError);
}

// A copy of `file` with `count` bytes at the n-th occurrence (from `from`) of `needle` replaced by
// `replacement`, padded with blanks to `count` bytes.
std::filesystem::path patched(const std::filesystem::path& file, const std::string& name,
                              const std::string& needle, std::size_t from,
                              const std::string& replacement, std::size_t count) {
  std::string bytes = test::readFile(file);
  const std::size_t at = bytes.find(needle, from);
  EXPECT_NE(at, std::string::npos) << needle;
  std::string text = replacement;
  text.resize(count, ' ');
  bytes.replace(at, count, text);
  const std::filesystem::path out = file.parent_path() / name;
  std::FILE* f = std::fopen(out.c_str(), "wb");
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  return out;
}

// Byte offset of the data of HDU `hdu` (1-based), from cfitsio.
std::size_t dataStart(const std::filesystem::path& file, int hdu) {
  fitsfile* f = nullptr;
  int status = 0;
  fits_open_file(&f, file.c_str(), READONLY, &status);
  fits_movabs_hdu(f, hdu, nullptr, &status);
  LONGLONG head = 0, data = 0, end = 0;
  fits_get_hduaddrll(f, &head, &data, &end, &status);
  fits_close_file(f, &status);
  EXPECT_EQ(status, 0);
  return std::size_t(data);
}

// readInputCatalog refuses the file, naming it and every fragment, and nothing is appended.
void expectRefused(const std::filesystem::path& file, const std::vector<std::string>& fragments) {
  try {
    readInputCatalog(file.string());
    ADD_FAILURE() << "no IoError for " << file;
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string() + ": "), std::string::npos) << what;
    for (const std::string& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  const Table add = octopoleTable(3);
  const std::filesystem::path out = file.string() + ".out";
  EXPECT_THROW(writeAppendedCatalog(file.string(), out.string(), {&add}), IoError);
  EXPECT_FALSE(std::filesystem::exists(out));
}

// Found by mutation fuzzing: a table claiming 2^31 rows in a 20 KB file made readInputCatalog
// allocate 16 GiB before cfitsio noticed; 2e8 rows cost 1.6 GB. The data size is checked
// against the file first.
TEST_F(InputCatalog, RowCountsTheFileCannotHoldAreRefusedBeforeAllocation) {
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::size_t objects = test::readFile(cat).find("LDAC_OBJECTS");
  for (const long long rows : {2147483648LL, 200000000LL}) {
    char card[81];
    std::snprintf(card, sizeof card, "NAXIS2  = %20lld", rows);
    const auto bad =
        patched(cat, "rows" + std::to_string(rows) + ".ldac", "NAXIS2  =", objects - 800, card, 30);
    expectRefused(bad, {"HDU 2", "truncated", "x " + std::to_string(rows)});
  }
}

// An extension type cfitsio does not know is read as an image HDU: appending then copied the
// corrupt HDU into an output that failed fitsverify.
TEST_F(InputCatalog, HduOfUnknownTypeIsRefused) {
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const auto bad = patched(cat, "foo.ldac", "XTENSION= 'BINTABLE'", 0, "XTENSION= 'FOO     '", 20);
  expectRefused(bad, {"HDU 1", "XTENSION 'FOO'"});
}

// Found by fuzzing: an unquoted TTYPEn value of 70 characters overflows a buffer in cfitsio 4.2
// (abort); the header is refused before cfitsio parses it.
TEST_F(InputCatalog, UnquotedColumnNameIsRefusedBeforeCfitsioReadsIt) {
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::size_t objects = test::readFile(cat).find("LDAC_OBJECTS");
  const auto bad = patched(cat, "ttype.ldac", "TTYPE1  = 'NUMBER", objects - 1200,
                           "TTYPE1  = " + std::string(70, 'A'), 80);
  expectRefused(bad, {"HDU 2: 'TTYPE1' is not a quoted string"});
}

TEST_F(InputCatalog, ImheadCellMustHoldCardsCfitsioCanParse) {
  const auto cat = test::runSourceExtractor(dir_, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::size_t cell = dataStart(cat, 2);
  // A terminal escape in a value, a keyword FITS does not allow, a value cfitsio cannot parse.
  expectRefused(patched(cat, "esc.ldac", "OBJECT  = 'test", cell, "OBJECT  = '\x1b[31m'", 20),
                {"LDAC_IMHEAD (HDU 1)", "card 8 'OBJECT  = '\\x1B[31m''", "not printable ASCII"});
  expectRefused(patched(cat, "key.ldac", "OBJECT  = 'test", cell, "OB?ECT  = 'test'", 20),
                {"LDAC_IMHEAD (HDU 1)", "illegal keyword 'OB?ECT'"});
  expectRefused(patched(cat, "value.ldac", "GAIN    =", cell, "GAIN    = (1,", 80),
                {"LDAC_IMHEAD (HDU 1)", "card 7 'GAIN    = (1,'", "cannot parse"});
  // The cell's END card blanked out.
  expectRefused(patched(cat, "noend.ldac", "END" + std::string(77, ' '), cell, "", 80),
                {"LDAC_IMHEAD (HDU 1)", "no END card"});
  // The same cards are read when nothing is wrong: 8 image cards and 46 SEx* cards.
  EXPECT_EQ(readInputCatalog(cat.string())[0].imageHeader.cards.size(), 54u);
}

}  // namespace
}  // namespace octarc

namespace octarc {
namespace {

// The LDAC_IMHEAD a FitsTable writer makes (a search's candidates.fits) holds every card of the
// image header and the run's, not only the first: cfitsio takes the cell, TDIM (80, n), for n
// strings of 80 characters.
TEST(LdacImheadTable, EveryCardReadsBack) {
  const std::filesystem::path dir = test::scratchDir();
  const FitsHeader image =
      test::imageHeader(100, 50, {{"CTYPE1", "'RA---TAN'"}, {"CRVAL1", "150.25"}});
  const std::string path = (dir / "imhead.fits").string();
  writeFitsTables(path, {ldacImheadTable(image, {formatCard("OCTVERS", std::string("0.1.0"))})});
  const FitsHeader back = readLdacImageHeader(path);
  EXPECT_EQ(back.number("NAXIS1"), 100.0);
  EXPECT_EQ(back.number("CRVAL1"), 150.25);
  EXPECT_EQ(back.value("CTYPE1"), "RA---TAN");
  EXPECT_EQ(back.value("OCTVERS"), "0.1.0");
}

}  // namespace
}  // namespace octarc
