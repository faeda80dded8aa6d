#include "octarc/selection/SearchSpace.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

std::string checkedName(std::string name) {
  if (name.find_first_not_of(" \t") == std::string::npos) {
    throw ConfigError("a search space needs a name");
  }
  return name;
}

}  // namespace

SearchSpace::SearchSpace(std::string name, std::string expression, const std::string& key)
    : name_(checkedName(std::move(name))),
      cut_(std::move(expression),
           (key.empty() ? std::string() : key + " ") + "search space '" + name_ + "'") {}

std::vector<bool> SearchSpace::mask(const Table& table) const {
  const std::vector<double> values = cut_.evaluate(table);
  std::vector<bool> keep(values.size());
  for (std::size_t r = 0; r < values.size(); ++r) {
    keep[r] = std::isfinite(values[r]) && values[r] != 0.0;
  }
  return keep;
}

std::vector<bool> SearchSpace::simulatedMask(const Table& simulated) const {
  std::vector<bool> keep = mask(simulated);
  if (countSelected(keep) == 0) {
    throw ConfigError("search space '" + name_ + "' (" + expression() +
                      "): no simulated row passes (of " + std::to_string(simulated.rows()) + ")");
  }
  return keep;
}

std::int64_t countSelected(const std::vector<bool>& mask) {
  return std::int64_t(std::count(mask.begin(), mask.end(), true));
}

}  // namespace octarc
