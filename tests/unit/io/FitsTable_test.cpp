// FitsTable: round trips of every column and keyword type, astropy reading what it writes and
// writing what it reads, fitsverify, and the one-line errors.
#include "octarc/io/FitsTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "ExpectError.h"
#include "TestCommands.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

std::string astropyScript() {
  return std::string(OCTARC_SOURCE_DIR) + "/tests/unit/io/fits_table_astropy.py";
}

using test::expectIoError;

FitsColumn column(std::string name, FitsColumnValues values, int repeat = 1, std::string unit = "",
                  std::string display = "", std::string comment = "") {
  FitsColumn c;
  c.name = std::move(name);
  c.values = std::move(values);
  c.repeat = repeat;
  c.unit = std::move(unit);
  c.display = std::move(display);
  c.comment = std::move(comment);
  return c;
}

const std::string kLongText = "a string longer than one card: " + std::string(60, 'x') +
                              " it's quoted " + std::string(40, 'y') + " end";

// Two tables holding every column type (extreme values included) and every keyword type.
std::vector<FitsTable> sampleTables() {
  FitsTable first;
  first.name = "FIRST";
  first.columns = {
      column("I16", std::vector<std::int16_t>{-32768, 0, 32767}, 1, "", "I6", "an int16"),
      column("I32", std::vector<std::int32_t>{-2147483647 - 1, 7, 2147483647}, 1, "count"),
      // 2^53 + 1 is not a double: only an exact int64 path keeps it.
      column("I64",
             std::vector<std::int64_t>{std::numeric_limits<std::int64_t>::min(), 9007199254740993LL,
                                       std::numeric_limits<std::int64_t>::max()}),
      column("F32", std::vector<float>{1.5f, std::nanf(""), -0.25f}, 1, "mag", "F8.3"),
      column("F64", std::vector<double>{0.1, 1e-300, kNaN}, 1, "deg", "", "a float64"),
      column("NAME", std::vector<std::string>{"lens", "", "arc 'x'"}, 8),
      column("AUTO", std::vector<std::string>{"a", "longest", "b"}, 0),
      column("VEC", std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}, 3, "pixel", "E12.4",
             "a vector"),
      column("BIN", std::vector<std::int32_t>{0, 1, 2, 3, 4, 5}, 2),
  };
  first.keywords = {
      FitsKeyword::logical("YES", true, "true"),
      FitsKeyword::logical("NO", false, "false"),
      FitsKeyword::integer("NEG", -123456789012LL, "negative integer"),
      FitsKeyword::unsignedInteger("SEED", std::numeric_limits<std::uint64_t>::max(), "2^64-1"),
      FitsKeyword::real("PIXSCALE", 0.257, "arcsec/px"),
      FitsKeyword::real("GAIN", 54.0, "e-/ADU"),
      FitsKeyword::real("TINY", 1.25e-7),
      FitsKeyword::real("UNKNOWN", kNaN, "not known"),
      FitsKeyword::text("SHORT", "it's", "a quote inside"),
      FitsKeyword::text("LONG", kLongText, "continued"),
  };
  FitsTable second;
  second.name = "SECOND";
  second.columns = {column("EMPTY", std::vector<double>{})};
  second.keywords = {FitsKeyword::integer("NROWS", 0)};
  return {first, second};
}

TEST(FitsTable, RoundTripOfEveryColumnAndKeywordType) {
  const fs::path path = test::scratchDir() / "tables.fits";
  writeFitsTables(path.string(), sampleTables());
  EXPECT_EQ(listFitsTables(path.string()), (std::vector<std::string>{"FIRST", "SECOND"}));

  const FitsTable t = readFitsTable(path.string(), "first");  // EXTNAME is case-insensitive
  EXPECT_EQ(t.name, "FIRST");
  EXPECT_EQ(t.source, path.string());
  EXPECT_EQ(t.rows(), 3);
  ASSERT_EQ(t.columns.size(), 9u);
  EXPECT_EQ(t.integers("I16"), (std::vector<std::int64_t>{-32768, 0, 32767}));
  EXPECT_EQ(t.column("I16").type(), FitsColumnType::Int16);
  EXPECT_EQ(t.column("I16").display, "I6");
  EXPECT_EQ(t.column("I16").comment, "an int16");
  EXPECT_EQ(t.column("I32").unit, "count");
  EXPECT_EQ(t.column("I32").type(), FitsColumnType::Int32);
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(t.column("I64").values),
            (std::vector<std::int64_t>{std::numeric_limits<std::int64_t>::min(), 9007199254740993LL,
                                       std::numeric_limits<std::int64_t>::max()}));
  const auto& f32 = std::get<std::vector<float>>(t.column("F32").values);
  EXPECT_EQ(f32[0], 1.5f);
  EXPECT_TRUE(std::isnan(f32[1]));
  EXPECT_EQ(f32[2], -0.25f);
  EXPECT_EQ(t.column("F32").display, "F8.3");
  EXPECT_EQ(t.column("F32").tform, "1E");
  const std::vector<double> f64 = t.doubles("F64");
  EXPECT_EQ(f64[0], 0.1);
  EXPECT_EQ(f64[1], 1e-300);
  EXPECT_TRUE(std::isnan(f64[2]));
  EXPECT_EQ(t.column("F64").comment, "a float64");
  EXPECT_EQ(t.strings("NAME"), (std::vector<std::string>{"lens", "", "arc 'x'"}));
  EXPECT_EQ(t.column("NAME").repeat, 8);
  EXPECT_EQ(t.strings("AUTO"), (std::vector<std::string>{"a", "longest", "b"}));
  EXPECT_EQ(t.column("AUTO").repeat, 7);  // the longest value
  EXPECT_EQ(t.doubles("VEC", 3), (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(t.column("VEC").tform, "3D");
  EXPECT_EQ(t.column("VEC").display, "E12.4");
  EXPECT_EQ(t.integers("BIN", 2), (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(t.integers("bin", 0).size(), 6u);  // column names are case-insensitive

  EXPECT_TRUE(t.logical("YES"));
  EXPECT_FALSE(t.logical("NO"));
  EXPECT_EQ(t.integer("NEG"), -123456789012LL);
  EXPECT_EQ(t.unsignedInteger("SEED"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(t.number("PIXSCALE"), 0.257);
  EXPECT_EQ(t.number("GAIN"), 54.0);
  EXPECT_TRUE(std::holds_alternative<double>(t.findKeyword("GAIN")->value));
  EXPECT_EQ(t.number("TINY"), 1.25e-7);
  EXPECT_TRUE(std::isnan(t.number("UNKNOWN")));
  EXPECT_EQ(t.findKeyword("UNKNOWN")->comment, "not known");
  EXPECT_EQ(t.text("SHORT"), "it's");
  EXPECT_EQ(t.findKeyword("SHORT")->comment, "a quote inside");
  EXPECT_EQ(t.text("LONG"), kLongText);
  EXPECT_EQ(t.findKeyword("PIXSCALE")->comment, "arcsec/px");
  // The keywords come back in the order written, with nothing structural among them.
  std::vector<std::string> names;
  for (const FitsKeyword& k : t.keywords) names.push_back(k.name);
  EXPECT_EQ(names, (std::vector<std::string>{"YES", "NO", "NEG", "SEED", "PIXSCALE", "GAIN", "TINY",
                                             "UNKNOWN", "SHORT", "LONG"}));

  const FitsTable second = readFitsTable(path.string(), "SECOND");
  EXPECT_EQ(second.rows(), 0);
  EXPECT_TRUE(second.doubles("EMPTY").empty());
  EXPECT_EQ(second.integer("NROWS"), 0);
}

TEST(FitsTable, ReadsOnlyTheColumnsAsked) {
  const fs::path path = test::scratchDir() / "tables.fits";
  writeFitsTables(path.string(), sampleTables());
  const FitsTable t = readFitsTable(path.string(), "FIRST", {"f64", "NAME"});
  ASSERT_EQ(t.columns.size(), 2u);
  EXPECT_EQ(t.columns[0].name, "F64");
  EXPECT_EQ(t.columns[1].name, "NAME");
  EXPECT_EQ(t.rows(), 3);
  expectIoError(
      [&] {
        readFitsTable(path.string(), "FIRST", {"F64", "NOPE"});
      },
      {path.string() + "[FIRST]", "no column NOPE"});
}

TEST(FitsTable, AstropyReadsWhatItWrites) {
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path path = test::scratchDir() / "tables.fits";
  writeFitsTables(path.string(), sampleTables());
  std::string out;
  ASSERT_EQ(
      test::runCommand(
          "/usr/bin/python3 '" + astropyScript() + "' dump '" + path.string() + "' 2>&1", &out),
      0)
      << out;
  // Every value as written, in astropy's reading (reals as Python's shortest repr).
  const std::vector<std::string> expected = {
      "TABLE FIRST 3\n",
      "COLUMN I16|1I||I6|an int16|-32768,0,32767\n",
      "COLUMN I32|1J|count|||-2147483648,7,2147483647\n",
      "COLUMN I64|1K||||-9223372036854775808,9007199254740993,9223372036854775807\n",
      "COLUMN F32|1E|mag|F8.3||1.5,nan,-0.25\n",
      "COLUMN F64|1D|deg||a float64|0.1,1e-300,nan\n",
      "COLUMN NAME|8A||||lens,,arc 'x'\n",
      "COLUMN AUTO|7A||||a,longest,b\n",
      "COLUMN VEC|3D|pixel|E12.4|a vector|1.0,2.0,3.0,4.0,5.0,6.0,7.0,8.0,9.0\n",
      "COLUMN BIN|2J||||0,1,2,3,4,5\n",
      "KEY YES|T|true\n",
      "KEY NO|F|false\n",
      "KEY NEG|-123456789012|negative integer\n",
      "KEY SEED|18446744073709551615|2^64-1\n",
      "KEY PIXSCALE|0.257|arcsec/px\n",
      "KEY GAIN|54.0|e-/ADU\n",
      "KEY TINY|1.25e-07|\n",
      "KEY UNKNOWN|UNDEFINED|not known\n",
      "KEY SHORT|it's|a quote inside\n",
      "KEY LONG|" + kLongText + "|continued\n",
      "TABLE SECOND 0\n",
      "COLUMN EMPTY|1D||||\n",
      "KEY NROWS|0|\n",
  };
  for (const std::string& line : expected) {
    EXPECT_NE(out.find(line), std::string::npos) << "missing: " << line << "in:\n" << out;
  }
}

TEST(FitsTable, FitsverifyReportsNoError) {
  OCTARC_REQUIRE_PROGRAM("fitsverify");
  const fs::path path = test::scratchDir() / "tables.fits";
  writeFitsTables(path.string(), sampleTables());
  std::string report;
  test::runCommand("fitsverify '" + path.string() + "' 2>&1", &report);
  // No error; the one warning is for the undefined value that stands for NaN (legal since
  // FITS 4.0, which fitsverify still flags).
  EXPECT_NE(report.find("1 warning(s) and 0 error(s)"), std::string::npos) << report;
  EXPECT_NE(report.find("UNKNOWN has a null value"), std::string::npos) << report;
  // Without it, a clean report.
  std::vector<FitsTable> tables = sampleTables();
  std::erase_if(tables[0].keywords, [](const FitsKeyword& k) { return k.name == "UNKNOWN"; });
  const fs::path clean = path.parent_path() / "clean.fits";
  writeFitsTables(clean.string(), tables);
  report.clear();
  test::runCommand("fitsverify -q '" + clean.string() + "' 2>&1", &report);
  EXPECT_NE(report.find("verification OK"), std::string::npos) << report;
}

TEST(FitsTable, ReadsWhatAstropyWrites) {
  if (!test::haveAstropy()) OCTARC_SKIP_MISSING() << "/usr/bin/python3 with astropy not available";
  const fs::path path = test::scratchDir() / "astropy.fits";
  std::string out;
  ASSERT_EQ(
      test::runCommand(
          "/usr/bin/python3 '" + astropyScript() + "' write '" + path.string() + "' 2>&1", &out),
      0)
      << out;
  // The values fits_table_astropy.py writes.
  const FitsTable t = readFitsTable(path.string(), "ASTROPY");
  EXPECT_EQ(t.rows(), 3);
  EXPECT_EQ(t.column("U16").type(), FitsColumnType::Int32);  // unsigned 16-bit, TZERO 32768
  EXPECT_EQ(t.integers("U16"), (std::vector<std::int64_t>{0, 40000, 65535}));
  EXPECT_EQ(t.column("BYTE").type(), FitsColumnType::Int16);
  EXPECT_EQ(t.integers("BYTE"), (std::vector<std::int64_t>{0, 200, 255}));
  EXPECT_EQ(t.strings("NAME"), (std::vector<std::string>{"a", "bc", "def"}));
  EXPECT_EQ(t.doubles("VEC", 2), (std::vector<double>{1.5, -2.25, 0.0, 4.0, 8.0, -0.5}));
  EXPECT_EQ(t.column("VEC").unit, "arcsec");
  expectIoError([&] { t.doubles("FLAG"); },
                {path.string() + "[ASTROPY] column FLAG", "TFORM = 'L'", "not supported"});
  EXPECT_EQ(t.text("SURVEY"), "DLS");
  EXPECT_EQ(t.findKeyword("SURVEY")->comment, "survey name");
  EXPECT_EQ(t.number("PIXSCALE"), 0.257);
  EXPECT_EQ(t.integer("NSYS"), 90000);
  EXPECT_TRUE(t.logical("DEEP"));
  std::string expr;
  for (int i = 0; i < 6; ++i) expr += "ARCNESS > 0.15 && ";
  EXPECT_EQ(t.text("EXPR"), expr + "SNR_ISO > 40");
}

TEST(FitsTable, ReadErrorsNameFileTableColumnAndKeyword) {
  const fs::path dir = test::scratchDir();
  const std::string path = (dir / "tables.fits").string();
  writeFitsTables(path, sampleTables());
  expectIoError([&] { readFitsTable(path, "THIRD"); },
                {path, "no binary table named THIRD", "tables: FIRST, SECOND"});
  const FitsTable t = readFitsTable(path, "FIRST");
  const std::string at = path + "[FIRST]";
  expectIoError([&] { t.doubles("MISSING"); }, {at, "no column MISSING"});
  expectIoError([&] { t.integers("F64"); }, {at, "column F64 is float64", "integer"});
  expectIoError([&] { t.doubles("NAME"); }, {at, "column NAME is string", "numeric"});
  expectIoError([&] { t.strings("I32"); }, {at, "column I32 is int32", "string"});
  expectIoError([&] { t.doubles("VEC"); }, {at, "column VEC has 3 elements per row, expected 1"});
  expectIoError([&] { t.number("NOPE"); }, {at, "keyword NOPE missing"});
  expectIoError([&] { t.integer("PIXSCALE"); }, {at, "keyword PIXSCALE is not"});
  expectIoError([&] { t.text("GAIN"); }, {at, "keyword GAIN is not a string"});
  expectIoError([&] { t.logical("SHORT"); }, {at, "keyword SHORT is not a logical"});
  expectIoError([&] { t.unsignedInteger("NEG"); }, {at, "keyword NEG is not a non-negative"});
  expectIoError([&] { t.integer("SEED"); }, {at, "keyword SEED is not a 64-bit signed"});

  // A file cut inside the rows of its first table.
  const std::string cut = (dir / "cut.fits").string();
  fs::copy_file(path, cut);
  fs::resize_file(cut, 2880 * 3 + 50);  // primary, FIRST's header (2 blocks), 50 bytes of rows
  expectIoError([&] { readFitsTable(cut, "FIRST"); },
                {cut + "[FIRST]", "truncated", "the table has 3 rows", "holds 0 complete rows"});

  const std::string text = (dir / "text.fits").string();
  std::FILE* f = std::fopen(text.c_str(), "w");
  std::fputs("not a FITS file\n", f);
  std::fclose(f);
  expectIoError([&] { readFitsTable(text, "FIRST"); }, {text});
  expectIoError([&] { readFitsTable((dir / "none.fits").string(), "FIRST"); }, {"none.fits"});
}

// cfitsio types an unquoted value by its first characters: "0.2abc" is typed a number. It is not
// read as 0.2 (nor "12abc" as 12): number() refuses it, naming the file and the keyword. The
// range-checked readers name the keyword, its value and the range.
TEST(FitsTable, KeywordValuesAreWholeNumbersInTheirRange) {
  const fs::path dir = test::scratchDir();
  const std::string path = (dir / "tables.fits").string();
  writeFitsTables(path, sampleTables());
  std::string bytes = test::readFile(path);
  for (const auto& [key, value] : {std::pair{"PIXSCALE", "0.2abc"}, std::pair{"NEG", "12abc"}}) {
    const std::size_t at = bytes.find(std::string(key).append(8 - std::strlen(key), ' ') + "= ");
    ASSERT_NE(at, std::string::npos) << key;
    bytes.replace(at + 10, 20, std::string(20 - std::strlen(value), ' ') + value);
  }
  const std::string patched = (dir / "patched.fits").string();
  test::writeTextFile(patched, bytes);
  const FitsTable bad = readFitsTable(patched, "FIRST");
  expectIoError([&] { bad.number("PIXSCALE"); },
                {patched + "[FIRST]", "keyword PIXSCALE is not a number"});
  expectIoError([&] { bad.integer("NEG"); }, {patched + "[FIRST]", "keyword NEG is not"});
  EXPECT_EQ(bad.number("GAIN"), 54.0);  // the cards around them read as before

  const FitsTable t = readFitsTable(path, "FIRST");
  const auto aboveOne = [](double v) { return v > 1.0; };
  EXPECT_EQ(t.number("GAIN", aboveOne, "a number > 1"), 54.0);
  expectIoError([&] { t.number("PIXSCALE", aboveOne, "a number > 1"); },
                {path + "[FIRST]", "PIXSCALE = 0.25700000000000001 is not a number > 1"});
  expectIoError([&] { t.number("UNKNOWN", aboveOne, "a number > 1"); },
                {"UNKNOWN = nan is not a number > 1"});
  EXPECT_EQ(t.integer("NEG", -123456789012LL, 0), -123456789012LL);
  expectIoError([&] { t.integer("NEG", 0, 255); },
                {path + "[FIRST]", "NEG = -123456789012 is not an integer from 0 to 255"});
}

TEST(FitsTable, WriteErrorsLeaveNoFile) {
  const fs::path dir = test::scratchDir();
  const std::string path = (dir / "bad.fits").string();
  auto expectRefused = [&](std::vector<FitsTable> tables, std::vector<std::string> fragments) {
    expectIoError([&] { writeFitsTables(path, tables); }, fragments);
    EXPECT_FALSE(fs::exists(path)) << fragments.front();
  };
  FitsTable t;
  t.name = "T";
  t.columns = {column("A", std::vector<double>{1, 2, 3, 4, 5}, 2)};
  expectRefused({t}, {path + "[T] column A", "5 values do not fill whole rows of 2"});
  t.columns = {column("A", std::vector<double>{1, 2}), column("B", std::vector<float>{1})};
  expectRefused({t}, {path + "[T] column B", "1 rows, but column A has 2"});
  t.columns = {column("A", std::vector<double>{1}), column("a", std::vector<double>{2})};
  expectRefused({t}, {"column name a given twice"});
  t.columns = {column("S", std::vector<std::string>{"toolong"}, 4)};
  expectRefused({t}, {"column S", "'toolong' is longer than the column width 4"});
  t.columns = {column("", std::vector<double>{1})};
  expectRefused({t}, {path + "[T]", "a column has no name"});
  t.columns = {column("A", std::vector<double>{1})};
  t.keywords = {FitsKeyword::real("NAXIS2", 3)};
  expectRefused({t}, {"keyword NAXIS2 is written by the table writer"});
  t.keywords = {FitsKeyword::real("TOOLONGNAME", 3)};
  expectRefused({t}, {"keyword name 'TOOLONGNAME'"});
  t.keywords = {FitsKeyword::real("INF", std::numeric_limits<double>::infinity())};
  expectRefused({t}, {"keyword INF is infinite"});
  t.keywords = {};
  t.name = "";
  expectRefused({t}, {path, "a table has no name"});

  // An existing file is never overwritten (callers write to an AtomicFile's temporary path).
  t.name = "T";
  writeFitsTables(path, {t});
  const auto size = fs::file_size(path);
  expectIoError([&] { writeFitsTables(path, {t, t}); }, {path, "cannot create"});
  EXPECT_EQ(fs::file_size(path), size);
}

TEST(FitsTable, PrimaryCardsAreWrittenVerbatim) {
  const fs::path path = test::scratchDir() / "primary.fits";
  const std::vector<std::string> cards = {"HISTORY   made by a test", "COMMENT a second card"};
  writeFitsTables(path.string(), sampleTables(), cards);
  const std::string bytes = test::readFile(path);
  // The primary header: SIMPLE, BITPIX, NAXIS, EXTEND and their two comment cards, then ours.
  ASSERT_GE(bytes.size(), 2880u);
  const std::string primary = bytes.substr(0, 2880);
  for (const std::string& card : cards) {
    EXPECT_NE(primary.find(card + std::string(80 - card.size(), ' ')), std::string::npos) << card;
  }
  EXPECT_EQ(listFitsTables(path.string()), (std::vector<std::string>{"FIRST", "SECOND"}));
  EXPECT_EQ(readFitsTable(path.string(), "FIRST").rows(), 3);
}

TEST(FitsTable, ReadsByHduIndexWithOptionalColumns) {
  const fs::path dir = test::scratchDir();
  const fs::path path = dir / "indexed.fits";
  writeFitsTables(path.string(), sampleTables());
  EXPECT_FALSE(hasFitsTableAt(path.string(), 0));  // the primary HDU is an image
  EXPECT_TRUE(hasFitsTableAt(path.string(), 1));
  EXPECT_TRUE(hasFitsTableAt(path.string(), 2));
  EXPECT_FALSE(hasFitsTableAt(path.string(), 3));
  EXPECT_FALSE(hasFitsTableAt(path.string(), -1));

  const FitsTable all = readFitsTableAt(path.string(), 1);
  EXPECT_EQ(all.name, "FIRST");
  EXPECT_EQ(all.columns.size(), 9u);
  EXPECT_EQ(all.integer("NEG"), -123456789012LL);

  // Required columns must exist; optional ones are read when present, in file order.
  const FitsTable some = readFitsTableAt(path.string(), 1, {"f64"}, {"NAME", "NOPE"});
  ASSERT_EQ(some.columns.size(), 2u);
  EXPECT_EQ(some.columns[0].name, "F64");
  EXPECT_EQ(some.columns[1].name, "NAME");
  EXPECT_EQ(some.strings("NAME"), (std::vector<std::string>{"lens", "", "arc 'x'"}));
  const FitsTable optionalOnly = readFitsTableAt(path.string(), 1, {}, {"I64", "NOPE"});
  ASSERT_EQ(optionalOnly.columns.size(), 1u);
  EXPECT_EQ(optionalOnly.integers("I64")[1], 9007199254740993LL);
  EXPECT_EQ(readFitsTableAt(path.string(), 2).name, "SECOND");

  const std::string at = path.string() + "[FIRST]";
  expectIoError([&] { readFitsTableAt(path.string(), 1, {"NOPE"}); }, {at, "no column NOPE"});
  expectIoError([&] { readFitsTableAt(path.string(), 0); },
                {path.string(), "HDU 0 is not a binary table"});
  expectIoError([&] { readFitsTableAt(path.string(), 5); },
                {path.string(), "HDU 5 is not a binary table"});

  // A table whose rows do not fit in the file is refused before anything is allocated.
  const std::string cut = (dir / "indexed-cut.fits").string();
  fs::copy_file(path, cut);
  fs::resize_file(cut, 2880 * 3 + 50);
  expectIoError([&] { readFitsTableAt(cut, 1); }, {cut});
  expectIoError([&] { hasFitsTableAt((dir / "none.fits").string(), 1); }, {"none.fits"});
}

TEST(FitsTable, TableFromFitsKeepsTheScalarNumericColumns) {
  FitsTable t;
  t.name = "OBJECTS";
  FitsColumn n;
  n.name = "NUMBER";
  n.values = std::vector<std::int32_t>{1, 2, 3};
  FitsColumn f;
  f.name = "FLUX";
  f.unit = "count";
  f.values = std::vector<float>{1.5f, std::nanf(""), -2.25f};
  FitsColumn v;
  v.name = "VEC";
  v.repeat = 2;
  v.values = std::vector<double>{1, 2, 3, 4, 5, 6};
  FitsColumn name;
  name.name = "NAME";
  name.values = std::vector<std::string>{"a", "b", "c"};
  t.columns = {n, f, v, name};
  const Table table = tableFromFits(t);
  ASSERT_EQ(table.columns().size(), 2u);  // the vector and the string columns are left out
  EXPECT_EQ(table.columns()[0].type, ColumnType::Int32);
  EXPECT_EQ(table.columns()[1].type, ColumnType::Float32);
  EXPECT_EQ(table.columns()[1].unit, "count");
  ASSERT_EQ(table.rows(), 3);
  EXPECT_EQ(table.value(2, 0), 3.0);
  EXPECT_EQ(table.value(0, 1), 1.5);
  EXPECT_TRUE(std::isnan(table.value(1, 1)));
  EXPECT_EQ(table.value(2, 1), -2.25);
}

}  // namespace
}  // namespace octarc
