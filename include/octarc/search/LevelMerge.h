// One candidate per physical object: the rows of a multi-threshold catalog that passed the
// selection, merged through the parent links of the component tree (core/Segment.h: an object
// at level k lies inside the object PARENT_NUMBER of level k - 1).
//
// A passing row joins its nearest passing ancestor (the first row up the parent chain that also
// passed), so an arc selected at levels 3, 4 and 7 is one candidate, and two arcs that split
// from one selected blob are one candidate with it; rows with no passing ancestor start their
// own. A parent missing from the rows (a filtered catalog) ends the walk up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace octarc {

// The identity of one catalog row in the component tree.
struct TreeRow {
  int level = 1;                  // THRESH_LEVEL
  std::int32_t number = 0;        // NUMBER within the level
  std::int32_t parentNumber = 0;  // PARENT_NUMBER (0 at level 1)
};

struct MergedObject {
  std::size_t bestRow = 0;        // the member row with the highest score
  std::vector<std::size_t> rows;  // every member row, ascending
  std::vector<int> passedLevels;  // the levels of the members, ascending, each once
};

// Merges the rows with passed[i] true. The best row of an object has the highest score (NaN
// ranking below every number), ties going to the lower level, then the lower row index. Objects are
// ordered by the score of their best row, highest first (ties by best row index). Throws
// ConfigError for rows, passed and score of different lengths or two rows with the same level and
// NUMBER.
std::vector<MergedObject> mergeAcrossLevels(const std::vector<TreeRow>& rows,
                                            const std::vector<bool>& passed,
                                            const std::vector<double>& score);

}  // namespace octarc
