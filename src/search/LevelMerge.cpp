#include "octarc/search/LevelMerge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

// Union-find over row indices (path halving; the root of a set is its smallest index).
std::size_t findRoot(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

void unite(std::vector<std::size_t>& parent, std::size_t a, std::size_t b) {
  a = findRoot(parent, a);
  b = findRoot(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

// A score to order by: NaN (a row that could not be scored) ranks below every number.
double rankingScore(double score) {
  return std::isnan(score) ? -std::numeric_limits<double>::infinity() : score;
}

// Whether row a is a better representative than row b.
bool better(const std::vector<TreeRow>& rows, const std::vector<double>& score, std::size_t a,
            std::size_t b) {
  const double sa = rankingScore(score[a]);
  const double sb = rankingScore(score[b]);
  if (sa != sb) return sa > sb;
  if (rows[a].level != rows[b].level) return rows[a].level < rows[b].level;
  return a < b;
}

}  // namespace

std::vector<MergedObject> mergeAcrossLevels(const std::vector<TreeRow>& rows,
                                            const std::vector<bool>& passed,
                                            const std::vector<double>& score) {
  if (passed.size() != rows.size() || score.size() != rows.size()) {
    throw ConfigError("level merge: " + std::to_string(rows.size()) + " rows but " +
                      std::to_string(passed.size()) + " selection flags and " +
                      std::to_string(score.size()) + " scores");
  }
  std::map<std::pair<int, std::int32_t>, std::size_t> rowOf;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rowOf.emplace(std::make_pair(rows[i].level, rows[i].number), i).second) {
      throw ConfigError("level merge: two rows are object " + std::to_string(rows[i].number) +
                        " of level " + std::to_string(rows[i].level));
    }
  }
  std::vector<std::size_t> parent(rows.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!passed[i]) continue;
    // Up the parent chain to the nearest passing ancestor.
    TreeRow at = rows[i];
    while (at.level > 1 && at.parentNumber > 0) {
      const auto up = rowOf.find({at.level - 1, at.parentNumber});
      if (up == rowOf.end()) break;
      if (passed[up->second]) {
        unite(parent, i, up->second);
        break;
      }
      at = rows[up->second];
    }
  }
  std::map<std::size_t, MergedObject> byRoot;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!passed[i]) continue;
    MergedObject& object = byRoot[findRoot(parent, i)];
    if (object.rows.empty() || better(rows, score, i, object.bestRow)) object.bestRow = i;
    object.rows.push_back(i);
    object.passedLevels.push_back(rows[i].level);
  }
  std::vector<MergedObject> objects;
  objects.reserve(byRoot.size());
  for (auto& [root, object] : byRoot) {
    std::sort(object.passedLevels.begin(), object.passedLevels.end());
    object.passedLevels.erase(std::unique(object.passedLevels.begin(), object.passedLevels.end()),
                              object.passedLevels.end());
    objects.push_back(std::move(object));
  }
  std::sort(objects.begin(), objects.end(), [&](const MergedObject& a, const MergedObject& b) {
    const double sa = rankingScore(score[a.bestRow]);
    const double sb = rankingScore(score[b.bestRow]);
    if (sa != sb) return sa > sb;
    return a.bestRow < b.bestRow;
  });
  return objects;
}

}  // namespace octarc
