// An in-memory catalog table: declared columns and rows of values.
//
// Values are held as double whatever the declared storage type (every int32 and float is exact
// in a double); writers convert to the declared ColumnType. A row is a flat block of
// rowWidth() doubles, column c occupying [offset(c), offset(c) + columns()[c].repeat).
// Rows live in fixed-size chunks, so that a catalog of millions of rows grows without ever
// being reallocated and copied; a row pointer stays valid until the table shrinks.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/core/UninitializedAllocator.h"

namespace octarc {

class Table {
 public:
  // Rows are kept in chunks: small ones by default; a table that will hold a whole survey
  // catalog asks for large ones (several MiB, which the allocator puts on huge pages).
  enum class Chunks { Small, Large };

  Table() = default;
  explicit Table(std::vector<ColumnSpec> columns, Chunks chunks = Chunks::Small);

  const std::vector<ColumnSpec>& columns() const { return columns_; }
  int columnCount() const { return static_cast<int>(columns_.size()); }
  int rowWidth() const { return rowWidth_; }
  int offset(int column) const { return offsets_[column]; }
  // Index of the column with this name (exact match), or -1.
  int findColumn(std::string_view name) const;
  // The same, ConfigError("<context>: the table has no column <name>") when there is none.
  int requireColumn(std::string_view name, std::string_view context) const;

  std::int64_t rows() const { return rows_; }
  // Appends a row filled with zeros and returns a pointer to it.
  double* appendRow();
  // Appends a row whose values are unset, for a caller that writes all of them (possibly on
  // another thread: the row's memory is then first touched there).
  double* appendRowUnset();
  double* row(std::int64_t r) {
    return chunks_[std::size_t(r >> chunkShift_)].data() + (r & chunkMask_) * rowWidth_;
  }
  const double* row(std::int64_t r) const {
    return chunks_[std::size_t(r >> chunkShift_)].data() + (r & chunkMask_) * rowWidth_;
  }
  double value(std::int64_t r, int column, int element = 0) const {
    return row(r)[offsets_[column] + element];
  }
  void setValue(std::int64_t r, int column, double v, int element = 0) {
    row(r)[offsets_[column] + element] = v;
  }
  // Keeps only the rows for which keep[r] is true, in order.
  void filterRows(const std::vector<bool>& keep);

 private:
  std::vector<ColumnSpec> columns_;
  std::vector<int> offsets_;
  int rowWidth_ = 0;
  // 2^chunkShift_ rows per chunk.
  int chunkShift_ = 10;
  std::int64_t chunkMask_ = (std::int64_t(1) << 10) - 1;
  std::int64_t rows_ = 0;
  std::vector<std::vector<double, UninitializedAllocator<double>>> chunks_;
};

}  // namespace octarc
