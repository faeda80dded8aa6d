#include "octarc/core/Table.h"

#include <algorithm>

namespace octarc {

Table::Table(std::vector<ColumnSpec> columns) : columns_(std::move(columns)) {
  offsets_.reserve(columns_.size());
  for (const ColumnSpec& c : columns_) {
    offsets_.push_back(rowWidth_);
    rowWidth_ += c.repeat;
  }
}

int Table::findColumn(std::string_view name) const {
  for (int i = 0; i < columnCount(); ++i) {
    if (columns_[i].name == name) return i;
  }
  return -1;
}

double* Table::appendRow() {
  values_.resize(values_.size() + std::size_t(rowWidth_), 0.0);
  return values_.data() + values_.size() - std::size_t(rowWidth_);
}

void Table::filterRows(const std::vector<bool>& keep) {
  std::size_t out = 0;
  const std::size_t width = std::size_t(rowWidth_);
  for (std::int64_t r = 0; r < rows(); ++r) {
    if (!keep[std::size_t(r)]) continue;
    if (out != std::size_t(r)) {
      std::copy_n(values_.begin() + std::ptrdiff_t(std::size_t(r) * width), width,
                  values_.begin() + std::ptrdiff_t(out * width));
    }
    ++out;
  }
  values_.resize(out * width);
}

}  // namespace octarc
