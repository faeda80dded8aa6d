// Small tables for the selection tests (error checks: tests/support/ExpectError.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ExpectError.h"
#include "octarc/core/Table.h"

namespace octarc::test {

// A table of float64 scalar columns, filled from equally long value lists.
inline Table makeTable(const std::vector<std::pair<std::string, std::vector<double>>>& columns) {
  std::vector<ColumnSpec> specs;
  for (const auto& [name, values] : columns) {
    ColumnSpec spec;
    spec.name = name;
    spec.type = ColumnType::Float64;
    specs.push_back(spec);
  }
  Table table(specs);
  const std::size_t rows = columns.empty() ? 0 : columns[0].second.size();
  for (std::size_t r = 0; r < rows; ++r) {
    double* row = table.appendRow();
    for (std::size_t c = 0; c < columns.size(); ++c) row[c] = columns[c].second[r];
  }
  return table;
}

}  // namespace octarc::test
