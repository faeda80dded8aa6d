// The FITS catalog rows: a table of several MB (more than one 4 MB write block) with every storage
// type, scalar and vector, read back value by value with cfitsio and compared byte for byte with
// the data area that cfitsio itself writes from typed column arrays; and tables with 0 rows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "CatalogTestSupport.h"
#include "TestPaths.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/core/Error.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {
namespace {

std::vector<ColumnSpec> mixedColumns() {
  auto col = [](const char* name, ColumnType type, const char* format, int repeat) {
    return ColumnSpec{name, std::string("Test column ") + name, "", "", type, format, repeat};
  };
  // 2+4+8+4+8 + 6+8+16+12+16 + 4+4 = 92 bytes and 19 values per row; 12 columns of 3 cards
  // each (no unit) and the 9 structural cards put the header into a second 2880-byte block.
  return {
      col("I16", ColumnType::Int16, "%6d", 1),
      col("I32", ColumnType::Int32, "%10d", 1),
      col("I64", ColumnType::Int64, "%20d", 1),
      col("F32", ColumnType::Float32, "%12.7g", 1),
      col("F64", ColumnType::Float64, "%18.10e", 1),
      col("V_I16", ColumnType::Int16, "%6d", 3),
      col("V_I32", ColumnType::Int32, "%10d", 2),
      col("V_I64", ColumnType::Int64, "%20d", 2),
      col("V_F32", ColumnType::Float32, "%12.7g", 3),
      col("V_F64", ColumnType::Float64, "%18.10e", 2),
      col("F32_B", ColumnType::Float32, "%12.7g", 1),
      col("I32_B", ColumnType::Int32, "%10d", 1),
  };
}

constexpr std::int64_t kRowBytes = 92;
constexpr int kRowValues = 19;

// Row values that reach every conversion case: ties (rounded to even), values beyond each
// integer range (clamped), NaN (0 in integer columns), infinities, float overflow and underflow.
double testValue(std::int64_t row, int index) {
  static const double kSpecial[] = {
      std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::infinity(),
      -std::numeric_limits<double>::infinity(),
      2.5,
      -3.5,
      0.5,
      -0.5,
      32767.5,
      -32768.7,
      40000.0,
      2147483647.4,
      -2147483649.0,
      3.0e9,
      1.0e19,
      -1.0e19,
      9007199254740993.0,
      1.0e39,   // overflows float
      1.0e-46,  // underflows float
      -0.0,
  };
  const std::int64_t k = row * 31 + index * 7;
  constexpr std::int64_t nSpecial = std::int64_t(sizeof kSpecial / sizeof kSpecial[0]);
  if (k % 11 == 0) return kSpecial[(k / 11) % nSpecial];
  // Smooth values of both signs, with fractions, up to a few 10^5.
  return (double((k * 2654435761LL) % 1000003) - 500000.0) * 0.37;
}

Table makeTable(std::int64_t rows, std::int64_t firstRow) {
  Table table(mixedColumns());
  for (std::int64_t r = 0; r < rows; ++r) {
    double* row = table.appendRow();
    for (int i = 0; i < table.rowWidth(); ++i) row[i] = testValue(firstRow + r, i);
  }
  return table;
}

// What an integer column must hold: rounded to nearest (ties to even), clamped, NaN as 0.
template <typename Int>
Int expectedInteger(double value) {
  if (std::isnan(value)) return 0;
  const double rounded = std::nearbyint(value);
  const double lo = double(std::numeric_limits<Int>::min());
  if (rounded <= lo) return std::numeric_limits<Int>::min();
  if (sizeof(Int) == 8) {
    if (rounded >= 9223372036854775807.0) return Int(9223372036854774784LL);
  } else if (rounded >= double(std::numeric_limits<Int>::max())) {
    return std::numeric_limits<Int>::max();
  }
  return Int(rounded);
}

// The reference data area: the same table written by cfitsio from typed column arrays
// (fits_write_col converts to big-endian itself).
void writeWithCfitsioColumns(const std::filesystem::path& file,
                             const std::vector<const Table*>& parts) {
  const std::vector<ColumnSpec> columns = mixedColumns();
  std::int64_t rows = 0;
  for (const Table* t : parts) rows += t->rows();
  std::vector<std::string> names;
  std::vector<std::string> forms;
  for (const ColumnSpec& c : columns) {
    names.push_back(c.name);
    forms.push_back(tformOf(c));
  }
  std::vector<char*> ttype;
  std::vector<char*> tform;
  for (std::string& s : names) ttype.push_back(s.data());
  for (std::string& s : forms) tform.push_back(s.data());
  detail::FitsPtr f = detail::createFits(file.string());
  int status = 0;
  fits_create_tbl(f.get(), BINARY_TBL, LONGLONG(rows), int(columns.size()), ttype.data(),
                  tform.data(), nullptr, "OBJECTS", &status);
  ASSERT_EQ(status, 0) << detail::cfitsioMessage(status);
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const int repeat = columns[c].repeat;
    std::vector<std::int16_t> i16;
    std::vector<std::int32_t> i32;
    std::vector<LONGLONG> i64;
    std::vector<float> f32;
    std::vector<double> f64;
    for (const Table* t : parts) {
      for (std::int64_t r = 0; r < t->rows(); ++r) {
        for (int e = 0; e < repeat; ++e) {
          const double v = t->value(r, int(c), e);
          i16.push_back(expectedInteger<std::int16_t>(v));
          i32.push_back(expectedInteger<std::int32_t>(v));
          i64.push_back(expectedInteger<std::int64_t>(v));
          f32.push_back(float(v));
          f64.push_back(v);
        }
      }
    }
    const LONGLONG n = LONGLONG(f64.size());
    const int colnum = int(c) + 1;
    switch (columns[c].type) {
      case ColumnType::Int16:
        fits_write_col(f.get(), TSHORT, colnum, 1, 1, n, i16.data(), &status);
        break;
      case ColumnType::Int32:
        fits_write_col(f.get(), TINT, colnum, 1, 1, n, i32.data(), &status);
        break;
      case ColumnType::Int64:
        fits_write_col(f.get(), TLONGLONG, colnum, 1, 1, n, i64.data(), &status);
        break;
      case ColumnType::Float32:
        fits_write_col(f.get(), TFLOAT, colnum, 1, 1, n, f32.data(), &status);
        break;
      case ColumnType::Float64:
        fits_write_col(f.get(), TDOUBLE, colnum, 1, 1, n, f64.data(), &status);
        break;
    }
    ASSERT_EQ(status, 0) << detail::cfitsioMessage(status);
  }
  fits_close_file(f.release(), &status);
  ASSERT_EQ(status, 0) << detail::cfitsioMessage(status);
}

std::map<std::string, std::string> headerValues(const std::filesystem::path& file, int hdu) {
  std::map<std::string, std::string> header;
  for (const auto& c : test::headerCards(file, hdu)) header[c.key] = c.value;
  return header;
}

// Reads every column of table HDU `hdu` back with cfitsio (in the column's own type) and counts
// the values that differ from what `parts` declare; reports the first few.
void expectRowsReadBack(const std::filesystem::path& file, int hdu,
                        const std::vector<const Table*>& parts) {
  const std::vector<ColumnSpec> columns = mixedColumns();
  std::int64_t rows = 0;
  for (const Table* t : parts) rows += t->rows();
  detail::FitsPtr f = detail::openFits(file.string());
  int status = 0;
  fits_movabs_hdu(f.get(), hdu, nullptr, &status);
  LONGLONG fileRows = 0;
  fits_get_num_rowsll(f.get(), &fileRows, &status);
  ASSERT_EQ(status, 0) << detail::cfitsioMessage(status);
  ASSERT_EQ(fileRows, rows);
  std::int64_t checked = 0;
  std::int64_t wrong = 0;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const ColumnSpec& spec = columns[c];
    const LONGLONG n = LONGLONG(rows * spec.repeat);
    std::vector<LONGLONG> integers(static_cast<std::size_t>(n));
    std::vector<double> reals(static_cast<std::size_t>(n));
    int anyNull = 0;
    const bool integer = spec.type == ColumnType::Int16 || spec.type == ColumnType::Int32 ||
                         spec.type == ColumnType::Int64;
    if (n > 0) {
      if (integer) {
        fits_read_col(f.get(), TLONGLONG, int(c) + 1, 1, 1, n, nullptr, integers.data(), &anyNull,
                      &status);
      } else {
        fits_read_col(f.get(), TDOUBLE, int(c) + 1, 1, 1, n, nullptr, reals.data(), &anyNull,
                      &status);
      }
    }
    ASSERT_EQ(status, 0) << spec.name << ": " << detail::cfitsioMessage(status);
    std::size_t at = 0;
    for (const Table* t : parts) {
      for (std::int64_t r = 0; r < t->rows(); ++r) {
        for (int e = 0; e < spec.repeat; ++e, ++at) {
          const double v = t->value(r, int(c), e);
          bool same = false;
          switch (spec.type) {
            case ColumnType::Int16:
              same = integers[at] == expectedInteger<std::int16_t>(v);
              break;
            case ColumnType::Int32:
              same = integers[at] == expectedInteger<std::int32_t>(v);
              break;
            case ColumnType::Int64:
              same = integers[at] == expectedInteger<std::int64_t>(v);
              break;
            case ColumnType::Float32: {
              const double stored = double(float(v));
              same = std::isnan(stored) ? std::isnan(reals[at]) : reals[at] == stored;
              break;
            }
            case ColumnType::Float64:
              same = std::isnan(v) ? std::isnan(reals[at]) : reals[at] == v;
              break;
          }
          ++checked;
          if (!same && ++wrong <= 5) {
            ADD_FAILURE() << spec.name << " element " << at << ": written " << v << ", read "
                          << (integer ? double(integers[at]) : reals[at]);
          }
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(checked, rows * kRowValues);
}

TEST(CatalogRows, ManyRowsOfEveryTypeRoundTripInFits10) {
  const auto dir = test::scratchDir();
  // 70000 + 13 + 50001 rows: 11 MB in five 4 MB write blocks, parts not aligned on a block.
  const Table a = makeTable(70000, 0);
  const Table b = makeTable(13, 70000);
  const Table c = makeTable(50001, 70013);
  ASSERT_EQ(a.rowWidth(), kRowValues);
  CatalogPart pa;
  pa.objects = &a;
  CatalogPart pb = pa;
  pb.objects = &b;
  CatalogPart pc = pa;
  pc.objects = &c;
  const auto ours = dir / "many.fits";
  writeCatalog(ours.string(), CatalogType::Fits10, {pa, pb, pc});

  const auto header = headerValues(ours, 2);
  EXPECT_EQ(header.at("NAXIS2"), "120014");
  EXPECT_EQ(header.at("NAXIS1"), std::to_string(kRowBytes));
  EXPECT_EQ(header.at("TFIELDS"), "12");
  // Header (2 blocks) + data padded to whole blocks, nothing else.
  const std::uintmax_t dataBytes = std::uintmax_t(120014 * kRowBytes);
  const std::uintmax_t headerCards = test::headerCards(ours, 2).size();  // END not counted
  EXPECT_EQ(headerCards, 45u);
  const std::uintmax_t headerBlocks = (headerCards + 1 + 35) / 36;
  EXPECT_EQ(headerBlocks, 2u);
  EXPECT_EQ(std::filesystem::file_size(ours),
            2880u + headerBlocks * 2880u + (dataBytes + 2879u) / 2880u * 2880u);

  expectRowsReadBack(ours, 2, {&a, &b, &c});
  const auto reference = dir / "cfitsio.fits";
  writeWithCfitsioColumns(reference, {&a, &b, &c});
  const std::string ourBytes = test::tableBytes(ours, 2);
  EXPECT_EQ(ourBytes.size(), dataBytes);
  EXPECT_TRUE(ourBytes == test::tableBytes(reference, 2));

  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  const test::FitsverifyReport report = test::fitsverify(ours);
  EXPECT_EQ(report.warnings, 0) << report.text;
  EXPECT_EQ(report.errors, 0) << report.text;
}

TEST(CatalogRows, ManyRowsOfEveryTypeRoundTripInLdac) {
  const auto dir = test::scratchDir();
  const Table a = makeTable(60000, 0);  // 5.5 MB: two write blocks
  const Table b = makeTable(7, 60000);
  CatalogPart pa;
  pa.imageHeader.cards.push_back(std::string("SIMPLE  =                    T") +
                                 std::string(50, ' '));
  pa.objects = &a;
  CatalogPart pb = pa;
  pb.objects = &b;
  const auto ours = dir / "many.ldac";
  writeCatalog(ours.string(), CatalogType::FitsLdac, {pa, pb});
  ASSERT_EQ(test::hduCount(ours), 5);
  EXPECT_EQ(headerValues(ours, 3).at("NAXIS2"), "60000");
  EXPECT_EQ(headerValues(ours, 5).at("NAXIS2"), "7");
  // The second pair starts where the first table's padded data ends.
  EXPECT_EQ(test::imheadCards(ours, 4).size(), 2u);
  expectRowsReadBack(ours, 3, {&a});
  expectRowsReadBack(ours, 5, {&b});

  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  // What LDAC's own layout gives (source-extractor's files too): two warnings per LDAC_IMHEAD
  // (the blank in 'Field Header Card') and one per repeated LDAC_IMHEAD/LDAC_OBJECTS name.
  const test::FitsverifyReport report = test::fitsverify(ours);
  EXPECT_EQ(report.warnings, 6) << report.text;
  EXPECT_EQ(report.errors, 0) << report.text;
}

TEST(CatalogRows, TablesWithoutRowsAreValid) {
  const auto dir = test::scratchDir();
  const Table empty = makeTable(0, 0);
  const Table some = makeTable(5, 0);
  CatalogPart pe;
  pe.objects = &empty;
  CatalogPart ps = pe;
  ps.objects = &some;

  const auto fits10 = dir / "empty.fits";
  writeCatalog(fits10.string(), CatalogType::Fits10, {pe, pe});
  EXPECT_EQ(headerValues(fits10, 2).at("NAXIS2"), "0");
  EXPECT_EQ(headerValues(fits10, 2).at("NAXIS1"), std::to_string(kRowBytes));
  EXPECT_EQ(std::filesystem::file_size(fits10), 3u * 2880u);  // primary + 2 header blocks
  expectRowsReadBack(fits10, 2, {});

  // Empty parts between full ones add nothing.
  const auto mixed = dir / "mixed.fits";
  writeCatalog(mixed.string(), CatalogType::Fits10, {pe, ps, pe, ps});
  EXPECT_EQ(headerValues(mixed, 2).at("NAXIS2"), "10");
  expectRowsReadBack(mixed, 2, {&some, &some});

  // An empty LDAC_OBJECTS followed by another pair: the next HDU starts right after its header.
  const auto ldac = dir / "empty.ldac";
  writeCatalog(ldac.string(), CatalogType::FitsLdac, {pe, ps});
  ASSERT_EQ(test::hduCount(ldac), 5);
  EXPECT_EQ(headerValues(ldac, 3).at("NAXIS2"), "0");
  expectRowsReadBack(ldac, 3, {});
  expectRowsReadBack(ldac, 5, {&some});

  if (!test::haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
  for (const auto& file : {fits10, mixed}) {
    const test::FitsverifyReport report = test::fitsverify(file);
    EXPECT_EQ(report.warnings, 0) << report.text;
    EXPECT_EQ(report.errors, 0) << report.text;
  }
  // The two LDAC_IMHEAD warnings of each pair (the blank in 'Field Header Card') and one for
  // the repeated extension names.
  const test::FitsverifyReport report = test::fitsverify(ldac);
  EXPECT_EQ(report.warnings, 6) << report.text;
  EXPECT_EQ(report.errors, 0) << report.text;
}

// A part whose rows are written in a given order is written as the table holding the rows in
// that order: the same bytes in every format; an order that does not list every row is refused.
TEST(CatalogRows, RowOrderWritesRowsInThatOrder) {
  const auto dir = test::scratchDir();
  const Table shuffledRows = makeTable(9001, 0);
  // Row k of the catalog is row order[k] of the table: a fixed scramble of 0..9000.
  std::vector<std::int64_t> order(9001);
  for (std::int64_t k = 0; k < 9001; ++k) order[std::size_t(k)] = (k * 7919) % 9001;
  Table inOrder(mixedColumns());
  for (const std::int64_t r : order) {
    std::copy_n(shuffledRows.row(r), shuffledRows.rowWidth(), inOrder.appendRow());
  }
  CatalogPart plain;
  plain.runCards.push_back(std::string("OCTNLEV =                    3") + std::string(50, ' '));
  plain.objects = &inOrder;
  CatalogPart ordered = plain;
  ordered.objects = &shuffledRows;
  ordered.rowOrder = &order;
  for (const CatalogType type :
       {CatalogType::FitsLdac, CatalogType::Fits10, CatalogType::AsciiHead}) {
    const std::string name = catalogTypeName(type);
    const auto a = dir / (name + "-plain");
    const auto b = dir / (name + "-ordered");
    writeCatalog(a.string(), type, {plain, plain});
    writeCatalog(b.string(), type, {ordered, plain});
    EXPECT_EQ(test::readFile(b), test::readFile(a)) << name;
  }
  expectRowsReadBack(dir / "FITS_LDAC-ordered", 3, {&inOrder});

  const std::vector<std::int64_t> shortOrder(order.begin(), order.end() - 1);
  ordered.rowOrder = &shortOrder;
  EXPECT_THROW(writeCatalog((dir / "bad.fits").string(), CatalogType::Fits10, {ordered}),
               std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.fits"));
}

}  // namespace
}  // namespace octarc
