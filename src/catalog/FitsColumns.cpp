#include "FitsColumns.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc::detail {

namespace {

std::string keyOf(const char* card) {
  std::string key(card, strnlen(card, 8));
  while (!key.empty() && key.back() == ' ') key.pop_back();
  return key;
}

// Column number of a column keyword such as TUNIT12 (letters after 'T', then digits), or 0.
int columnOfKeyword(const std::string& key) {
  if (key.size() < 2 || key[0] != 'T') return 0;
  std::size_t i = 1;
  while (i < key.size() && std::isupper(static_cast<unsigned char>(key[i]))) ++i;
  if (i == 1 || i == key.size()) return 0;
  int n = 0;
  for (std::size_t j = i; j < key.size(); ++j) {
    if (!std::isdigit(static_cast<unsigned char>(key[j]))) return 0;
    n = n * 10 + (key[j] - '0');
  }
  return n;
}

template <typename T>
void writeTyped(fitsfile* f, int datatype, int colnum, const Table& table, int column,
                const std::string& path, T (*convert)(ColumnType, double)) {
  const ColumnSpec& spec = table.columns()[std::size_t(column)];
  const std::int64_t rows = table.rows();
  const int repeat = spec.repeat;
  std::vector<T> values(std::size_t(rows * repeat));
  for (std::int64_t r = 0; r < rows; ++r) {
    for (int e = 0; e < repeat; ++e) {
      values[std::size_t(r * repeat + e)] = convert(spec.type, table.value(r, column, e));
    }
  }
  if (values.empty()) return;
  int status = 0;
  fits_write_col(f, datatype, colnum, 1, 1, LONGLONG(values.size()), values.data(), &status);
  throwIfFitsError(status, path, "cannot write column " + spec.name);
}

}  // namespace

bool isIntegerType(ColumnType type) {
  return type == ColumnType::Int16 || type == ColumnType::Int32 || type == ColumnType::Int64;
}

long long integerValue(ColumnType type, double value) {
  if (std::isnan(value)) return 0;
  double lo = double(std::numeric_limits<std::int64_t>::min());
  double hi = 9.2233720368547748e18;  // largest double below 2^63
  if (type == ColumnType::Int16) {
    lo = std::numeric_limits<std::int16_t>::min();
    hi = std::numeric_limits<std::int16_t>::max();
  } else if (type == ColumnType::Int32) {
    lo = std::numeric_limits<std::int32_t>::min();
    hi = std::numeric_limits<std::int32_t>::max();
  }
  const double rounded = std::nearbyint(value);
  if (rounded <= lo) return static_cast<long long>(lo);
  if (rounded >= hi) return static_cast<long long>(hi);
  return static_cast<long long>(rounded);
}

void writeColumnCards(fitsfile* f, int colnum, const ColumnSpec& column, const std::string& path) {
  int status = 0;
  const std::string n = std::to_string(colnum);
  for (const char* root : {"TTYPE", "TFORM", "TUNIT", "TDISP"}) {
    fits_delete_key(f, (root + n).c_str(), &status);
    if (status == KEY_NO_EXIST) status = 0;
    throwIfFitsError(status, path, "cannot update header of column " + column.name);
  }

  int nkeys = 0;
  int more = 0;
  fits_get_hdrspace(f, &nkeys, &more, &status);
  throwIfFitsError(status, path, "cannot read table header");
  int insertAt = 0;  // 1-based position of the first new card
  char card[FLEN_CARD];
  for (int k = 1; k <= nkeys; ++k) {
    fits_read_record(f, k, card, &status);
    throwIfFitsError(status, path, "cannot read table header");
    const std::string key = keyOf(card);
    if (colnum == 1 ? (key == "TFIELDS" || key == "EXTNAME") : columnOfKeyword(key) == colnum - 1) {
      insertAt = k + 1;
    }
  }
  if (insertAt == 0) insertAt = nkeys + 1;

  std::vector<std::string> cards;
  cards.push_back(formatCard("TTYPE" + n, column.name, column.description));
  cards.push_back(formatCard("TFORM" + n, tformOf(column)));
  if (!column.unit.empty()) cards.push_back(formatCard("TUNIT" + n, column.unit));
  const std::string tdisp = tdispFromPrintf(column.printfFormat);
  if (!tdisp.empty()) cards.push_back(formatCard("TDISP" + n, tdisp));
  for (const std::string& c : cards) {
    fits_insert_record(f, insertAt++, c.c_str(), &status);
    throwIfFitsError(status, path, "cannot write header of column " + column.name);
  }
}

void writeColumnData(fitsfile* f, int colnum, const Table& table, int column,
                     const std::string& path) {
  switch (table.columns()[std::size_t(column)].type) {
    case ColumnType::Int16:
      writeTyped<short>(f, TSHORT, colnum, table, column, path,
                        [](ColumnType t, double v) { return short(integerValue(t, v)); });
      break;
    case ColumnType::Int32:
      writeTyped<int>(f, TINT, colnum, table, column, path,
                      [](ColumnType t, double v) { return int(integerValue(t, v)); });
      break;
    case ColumnType::Int64:
      writeTyped<LONGLONG>(f, TLONGLONG, colnum, table, column, path,
                           [](ColumnType t, double v) { return LONGLONG(integerValue(t, v)); });
      break;
    case ColumnType::Float32:
      writeTyped<float>(f, TFLOAT, colnum, table, column, path,
                        [](ColumnType, double v) { return float(v); });
      break;
    case ColumnType::Float64:
      writeTyped<double>(f, TDOUBLE, colnum, table, column, path,
                         [](ColumnType, double v) { return v; });
      break;
  }
}

namespace {

// Appends `bytes` bytes of `value`'s representation, most significant first (FITS order).
template <typename T>
void putBigEndian(unsigned char*& out, T value) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) *out++ = raw[sizeof(T) - 1 - i];
}

std::size_t storageBytes(ColumnType type) {
  switch (type) {
    case ColumnType::Int16:
      return 2;
    case ColumnType::Int32:
      return 4;
    case ColumnType::Int64:
      return 8;
    case ColumnType::Float32:
      return 4;
    case ColumnType::Float64:
      return 8;
  }
  return 0;
}

}  // namespace

void writeTableRows(fitsfile* f, const Table& table, std::int64_t firstRow,
                    const std::string& path) {
  std::size_t rowBytes = 0;
  for (const ColumnSpec& c : table.columns())
    rowBytes += storageBytes(c.type) * std::size_t(c.repeat);
  if (rowBytes == 0 || table.rows() == 0) return;
  // About 4 MB per write.
  const std::int64_t rowsPerBlock =
      std::max<std::int64_t>(1, (std::int64_t(4) << 20) / std::int64_t(rowBytes));
  std::vector<unsigned char> block;
  for (std::int64_t r0 = 0; r0 < table.rows(); r0 += rowsPerBlock) {
    const std::int64_t r1 = std::min(table.rows(), r0 + rowsPerBlock);
    block.resize(std::size_t(r1 - r0) * rowBytes);
    unsigned char* out = block.data();
    for (std::int64_t r = r0; r < r1; ++r) {
      const double* row = table.row(r);
      for (int c = 0; c < table.columnCount(); ++c) {
        const ColumnSpec& spec = table.columns()[std::size_t(c)];
        const double* v = row + table.offset(c);
        for (int e = 0; e < spec.repeat; ++e) {
          switch (spec.type) {
            case ColumnType::Int16:
              putBigEndian(out, std::int16_t(integerValue(spec.type, v[e])));
              break;
            case ColumnType::Int32:
              putBigEndian(out, std::int32_t(integerValue(spec.type, v[e])));
              break;
            case ColumnType::Int64:
              putBigEndian(out, std::int64_t(integerValue(spec.type, v[e])));
              break;
            case ColumnType::Float32:
              putBigEndian(out, float(v[e]));
              break;
            case ColumnType::Float64:
              putBigEndian(out, v[e]);
              break;
          }
        }
      }
    }
    int status = 0;
    fits_write_tblbytes(f, LONGLONG(firstRow + r0 + 1), 1, LONGLONG(block.size()), block.data(),
                        &status);
    throwIfFitsError(status, path, "cannot write catalog rows");
  }
}

void closeWritten(fitsfile* f, const std::string& path) {
  int status = 0;
  fits_close_file(f, &status);
  throwIfFitsError(status, path, "cannot finish writing");
}

}  // namespace octarc::detail
