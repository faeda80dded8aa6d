#include "FitsColumns.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <thread>
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

// std::nearbyint() in the default rounding mode (to nearest, ties to even) without a library
// call: below 2^52 in magnitude, adding and removing 2^52 rounds to an integer, as the sum has
// no fraction bits left; larger values (and infinities) are integers already.
inline double roundToNearestEven(double value) {
  constexpr double kTwo52 = 4503599627370496.0;
  if (!(std::fabs(value) < kTwo52)) return value;
  const double shift = std::copysign(kTwo52, value);
  return (value + shift) - shift;
}

// integerValue() for one storage type: the bounds are compile-time constants, so that the row
// packer's inner loops stay free of branches on the type.
template <typename Int>
long long storedInteger(double value) {
  if (std::isnan(value)) return 0;
  constexpr double lo = double(std::numeric_limits<Int>::min());
  // For 64 bits the largest double below 2^63 (2^63 - 1 is not a double).
  constexpr double hi =
      sizeof(Int) == 8 ? 9.2233720368547748e18 : double(std::numeric_limits<Int>::max());
  const double rounded = roundToNearestEven(value);
  if (rounded <= lo) return static_cast<long long>(lo);
  if (rounded >= hi) return static_cast<long long>(hi);
  return static_cast<long long>(rounded);
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

std::vector<std::string> columnCards(int colnum, const ColumnSpec& column) {
  const std::string n = std::to_string(colnum);
  std::vector<std::string> cards;
  cards.push_back(formatCard("TTYPE" + n, column.name, column.description));
  cards.push_back(formatCard("TFORM" + n, tformOf(column)));
  if (!column.unit.empty()) cards.push_back(formatCard("TUNIT" + n, column.unit));
  const std::string tdisp = tdispFromPrintf(column.printfFormat);
  if (!tdisp.empty()) cards.push_back(formatCard("TDISP" + n, tdisp));
  return cards;
}

bool isIntegerType(ColumnType type) {
  return type == ColumnType::Int16 || type == ColumnType::Int32 || type == ColumnType::Int64;
}

long long integerValue(ColumnType type, double value) {
  switch (type) {
    case ColumnType::Int16:
      return storedInteger<std::int16_t>(value);
    case ColumnType::Int32:
      return storedInteger<std::int32_t>(value);
    default:
      return storedInteger<std::int64_t>(value);
  }
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

  for (const std::string& c : columnCards(colnum, column)) {
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

// Stores `bits` most significant byte first (FITS order).
inline void putBig(unsigned char* out, std::uint16_t bits) {
  bits = __builtin_bswap16(bits);
  std::memcpy(out, &bits, sizeof bits);
}
inline void putBig(unsigned char* out, std::uint32_t bits) {
  bits = __builtin_bswap32(bits);
  std::memcpy(out, &bits, sizeof bits);
}
inline void putBig(unsigned char* out, std::uint64_t bits) {
  bits = __builtin_bswap64(bits);
  std::memcpy(out, &bits, sizeof bits);
}

template <typename T>
std::uint32_t bits32(T value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

template <typename T>
std::uint64_t bits64(T value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Packs `n` row values of one storage type; returns the end of what it wrote.
template <ColumnType Type>
unsigned char* packValues(const double* in, int n, unsigned char* out);

template <>
unsigned char* packValues<ColumnType::Int16>(const double* in, int n, unsigned char* out) {
  for (int i = 0; i < n; ++i) {
    putBig(out + 2 * i, std::uint16_t(std::int16_t(storedInteger<std::int16_t>(in[i]))));
  }
  return out + 2 * n;
}

template <>
unsigned char* packValues<ColumnType::Int32>(const double* in, int n, unsigned char* out) {
  for (int i = 0; i < n; ++i) {
    putBig(out + 4 * i, bits32(std::int32_t(storedInteger<std::int32_t>(in[i]))));
  }
  return out + 4 * n;
}

template <>
unsigned char* packValues<ColumnType::Int64>(const double* in, int n, unsigned char* out) {
  for (int i = 0; i < n; ++i) {
    putBig(out + 8 * i, bits64(std::int64_t(storedInteger<std::int64_t>(in[i]))));
  }
  return out + 8 * n;
}

template <>
unsigned char* packValues<ColumnType::Float32>(const double* in, int n, unsigned char* out) {
  for (int i = 0; i < n; ++i) putBig(out + 4 * i, bits32(float(in[i])));
  return out + 4 * n;
}

template <>
unsigned char* packValues<ColumnType::Float64>(const double* in, int n, unsigned char* out) {
  for (int i = 0; i < n; ++i) putBig(out + 8 * i, bits64(in[i]));
  return out + 8 * n;
}

using PackFunction = unsigned char* (*)(const double*, int, unsigned char*);

PackFunction packFunction(ColumnType type) {
  switch (type) {
    case ColumnType::Int16:
      return packValues<ColumnType::Int16>;
    case ColumnType::Int32:
      return packValues<ColumnType::Int32>;
    case ColumnType::Int64:
      return packValues<ColumnType::Int64>;
    case ColumnType::Float32:
      return packValues<ColumnType::Float32>;
    case ColumnType::Float64:
      break;
  }
  return packValues<ColumnType::Float64>;
}

std::size_t storageBytes(ColumnType type) {
  switch (type) {
    case ColumnType::Int16:
      return 2;
    case ColumnType::Int32:
    case ColumnType::Float32:
      return 4;
    case ColumnType::Int64:
    case ColumnType::Float64:
      break;
  }
  return 8;
}

// The packing plan of chosen columns of a table, made once: adjacent columns of one type become
// one run, so that a catalog of float columns packs each row in a single tight loop.
std::vector<PackRun> packPlan(const Table& table, const std::vector<int>& columns,
                              std::size_t& rowBytes) {
  std::vector<PackRun> runs;
  rowBytes = 0;
  ColumnType previous = ColumnType::Float32;
  for (int c : columns) {
    const ColumnSpec& spec = table.columns()[std::size_t(c)];
    rowBytes += storageBytes(spec.type) * std::size_t(spec.repeat);
    if (!runs.empty() && spec.type == previous &&
        runs.back().first + runs.back().count == table.offset(c)) {
      runs.back().count += spec.repeat;
    } else {
      runs.push_back({packFunction(spec.type), table.offset(c), spec.repeat});
    }
    previous = spec.type;
  }
  return runs;
}

std::vector<PackRun> packPlan(const Table& table, std::size_t& rowBytes) {
  std::vector<int> all(std::size_t(table.columnCount()));
  for (int c = 0; c < table.columnCount(); ++c) all[std::size_t(c)] = c;
  return packPlan(table, all, rowBytes);
}

}  // namespace

RowPacker::RowPacker(const Table& table, const std::vector<int>& columns)
    : table_(&table), runs_(packPlan(table, columns, rowBytes_)) {}

unsigned char* RowPacker::pack(std::int64_t r, unsigned char* out) const {
  const double* row = table_->row(r);
  for (const PackRun& run : runs_) out = run.pack(row + run.first, run.count, out);
  return out;
}

void writeTableRows(fitsfile* f, const std::vector<TableRows>& tables, const std::string& path) {
  // Blocks of about 4 MB (large enough that cfitsio writes them straight to the file), taken
  // across the tables in order.
  struct Plan {
    std::vector<PackRun> runs;
    std::size_t rowBytes = 0;
  };
  struct Block {
    const TableRows* rows;
    const Plan* plan;
    std::int64_t k0, k1;   // positions in `rows`
    std::int64_t fileRow;  // 0-based row in the FITS table
  };
  std::vector<Plan> plans(tables.size());
  std::vector<Block> blocks;
  std::int64_t fileRow = 0;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableRows& t = tables[i];
    plans[i].runs = packPlan(*t.table, plans[i].rowBytes);
    const std::size_t rowBytes = plans[i].rowBytes;
    if (rowBytes == 0) continue;
    const std::int64_t rowsPerBlock =
        std::max<std::int64_t>(1, (std::int64_t(4) << 20) / std::int64_t(rowBytes));
    for (std::int64_t k0 = 0; k0 < t.rows(); k0 += rowsPerBlock) {
      const std::int64_t k1 = std::min(t.rows(), k0 + rowsPerBlock);
      blocks.push_back({&t, &plans[i], k0, k1, fileRow + k0});
    }
    fileRow += t.rows();
  }
  if (blocks.empty()) return;
  auto pack = [](const Block& b, std::vector<unsigned char>& buffer) {
    const std::vector<PackRun>& plan = b.plan->runs;
    buffer.resize(std::size_t(b.k1 - b.k0) * b.plan->rowBytes);
    unsigned char* out = buffer.data();
    const std::int64_t rowWidth = b.rows->table->rowWidth();
    for (std::int64_t k = b.k0; k < b.k1; ++k) {
      if (b.rows->order != nullptr && k + 8 < b.k1) {
        // Rows taken out of storage order: fetch a few rows ahead.
        const char* ahead = reinterpret_cast<const char*>(b.rows->table->row(b.rows->rowAt(k + 8)));
        for (std::int64_t byte = 0; byte < rowWidth * 8; byte += 64)
          __builtin_prefetch(ahead + byte);
      }
      const double* row = b.rows->table->row(b.rows->rowAt(k));
      for (const PackRun& run : plan) out = run.pack(row + run.first, run.count, out);
    }
  };
  // The next block is packed on a second thread while this one is written.
  std::vector<unsigned char> buffers[2];
  pack(blocks[0], buffers[0]);
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    std::thread packer;
    if (k + 1 < blocks.size()) {
      packer = std::thread(pack, std::cref(blocks[k + 1]), std::ref(buffers[(k + 1) % 2]));
    }
    std::vector<unsigned char>& block = buffers[k % 2];
    int status = 0;
    fits_write_tblbytes(f, LONGLONG(blocks[k].fileRow + 1), 1, LONGLONG(block.size()), block.data(),
                        &status);
    if (packer.joinable()) packer.join();
    throwIfFitsError(status, path, "cannot write catalog rows");
  }
}

void closeWritten(fitsfile* f, const std::string& path) {
  int status = 0;
  fits_close_file(f, &status);
  throwIfFitsError(status, path, "cannot finish writing");
}

}  // namespace octarc::detail
