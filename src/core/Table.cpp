#include "octarc/core/Table.h"

#include <algorithm>
#include <string>

#include "octarc/core/Error.h"

namespace octarc {

Table::Table(std::vector<ColumnSpec> columns, Chunks chunks) : columns_(std::move(columns)) {
  offsets_.reserve(columns_.size());
  for (const ColumnSpec& c : columns_) {
    offsets_.push_back(rowWidth_);
    rowWidth_ += c.repeat;
  }
  if (chunks == Chunks::Large) {
    // At least the allocator's large block, so that chunks come as huge pages.
    const std::size_t rowBytes = sizeof(double) * std::size_t(std::max(rowWidth_, 1));
    while ((std::size_t(1) << chunkShift_) * rowBytes <
           UninitializedAllocator<double>::kLargeBlock) {
      ++chunkShift_;
    }
  }
  chunkMask_ = (std::int64_t(1) << chunkShift_) - 1;
}

int Table::findColumn(std::string_view name) const {
  for (int i = 0; i < columnCount(); ++i) {
    if (columns_[i].name == name) return i;
  }
  return -1;
}

int Table::requireColumn(std::string_view name, std::string_view context) const {
  const int c = findColumn(name);
  if (c < 0) {
    throw ConfigError(std::string(context) + ": the table has no column " + std::string(name));
  }
  return c;
}

double* Table::appendRow() {
  double* r = appendRowUnset();
  std::fill_n(r, rowWidth_, 0.0);
  return r;
}

double* Table::appendRowUnset() {
  if ((rows_ & chunkMask_) == 0) {
    // Not zero-filled here: each row's memory is first written by whoever fills the row.
    chunks_.emplace_back(std::size_t((chunkMask_ + 1) * std::max(rowWidth_, 1)));
  }
  ++rows_;
  return row(rows_ - 1);
}

void Table::filterRows(const std::vector<bool>& keep) {
  std::int64_t out = 0;
  for (std::int64_t r = 0; r < rows_; ++r) {
    if (!keep[std::size_t(r)]) continue;
    if (out != r) std::copy_n(row(r), rowWidth_, row(out));
    ++out;
  }
  rows_ = out;
  // Whole chunks past the last row are released; the last one is zeroed beyond it, so that
  // appendRow() keeps handing out zero-filled rows.
  chunks_.resize(std::size_t((rows_ + chunkMask_) >> chunkShift_));
  if ((rows_ & chunkMask_) != 0) {
    auto& last = chunks_.back();
    std::fill(last.begin() + std::ptrdiff_t((rows_ & chunkMask_) * rowWidth_), last.end(), 0.0);
  }
}

}  // namespace octarc
