// Small tables and error checks for the selection tests.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

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

// Expects an exception of type E whose one-line message contains every fragment.
template <typename E, typename Fn>
void expectError(Fn&& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
    ADD_FAILURE() << "no exception (expected '" << fragments.front() << "')";
  } catch (const E& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    for (const std::string& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << what;
  }
}

}  // namespace octarc::test
