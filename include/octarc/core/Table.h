// An in-memory catalog table: declared columns and rows of values.
//
// Values are held as double whatever the declared storage type (every int32 and float is exact
// in a double); writers convert to the declared ColumnType. A row is a flat block of
// rowWidth() doubles, column c occupying [offset(c), offset(c) + columns()[c].repeat).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "octarc/core/Column.h"

namespace octarc {

class Table {
 public:
  Table() = default;
  explicit Table(std::vector<ColumnSpec> columns);

  const std::vector<ColumnSpec>& columns() const { return columns_; }
  int columnCount() const { return static_cast<int>(columns_.size()); }
  int rowWidth() const { return rowWidth_; }
  int offset(int column) const { return offsets_[column]; }
  // Index of the column with this name (exact match), or -1.
  int findColumn(std::string_view name) const;

  std::int64_t rows() const { return rowWidth_ == 0 ? 0 : std::int64_t(values_.size()) / rowWidth_; }
  void reserveRows(std::int64_t n) { values_.reserve(std::size_t(n * rowWidth_)); }
  // Appends a row filled with zeros and returns a pointer to it (valid until the next append).
  double* appendRow();
  double* row(std::int64_t r) { return values_.data() + r * rowWidth_; }
  const double* row(std::int64_t r) const { return values_.data() + r * rowWidth_; }
  double value(std::int64_t r, int column, int element = 0) const {
    return values_[std::size_t(r * rowWidth_ + offsets_[column] + element)];
  }
  void setValue(std::int64_t r, int column, double v, int element = 0) {
    values_[std::size_t(r * rowWidth_ + offsets_[column] + element)] = v;
  }
  // Keeps only the rows for which keep[r] is true, in order.
  void filterRows(const std::vector<bool>& keep);

 private:
  std::vector<ColumnSpec> columns_;
  std::vector<int> offsets_;
  int rowWidth_ = 0;
  std::vector<double> values_;
};

}  // namespace octarc
