// A search space (METHOD.md section 4): a named kind of arc, given as a cut on catalog columns,
// e.g. "ARCNESS > 0.15 && E_IMAGE > 0.6 && SNR_ISO > 40". It restricts both the simulated
// arcs an occupation grid is made of and the survey objects searched with it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {

class SearchSpace {
 public:
  // Throws ConfigError for an empty name, or an expression that is empty or does not parse
  // (see ColumnExpression), naming the space, and `key` when given (the configuration key it
  // came from, e.g. "SEARCH_SPACE").
  SearchSpace(std::string name, std::string expression, const std::string& key = "");

  const std::string& name() const { return name_; }
  const std::string& expression() const { return cut_.text(); }

  // Which rows of `table` are in the space: those where the cut evaluates to a finite non-zero
  // value (comparisons and && give 1 or 0; a row with NaN in a column the cut uses never
  // passes). ConfigError for an unknown column (see ColumnExpression::evaluate).
  std::vector<bool> mask(const Table& table) const;
  // The same for the simulated arcs a grid is filled with, where an empty space is an error:
  // ConfigError("search space '<name>' (<expression>): no simulated row passes (of N)").
  std::vector<bool> simulatedMask(const Table& simulated) const;

 private:
  std::string name_;
  ColumnExpression cut_;
};

// Number of true entries of a row mask.
std::int64_t countSelected(const std::vector<bool>& mask);

}  // namespace octarc
