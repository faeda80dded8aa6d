// Scoring catalog rows against an occupation grid (METHOD.md section 4): a survey object is kept
// when it falls in a selected bin; its score is that bin's probability and the contour level at
// which the bin enters (its cumulative probability, selection/OccupationGrid.h).
#pragma once

#include <cstdint>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/selection/OccupationGrid.h"

namespace octarc {

enum class ScoreStatus {
  OccupiedBin,  // in a bin simulated arcs occupy
  EmptyBin,     // inside the grid, in a bin no simulated arc occupies
  Outside,      // an axis value outside its range
  Undefined,    // an axis value NaN
};

struct RowScore {
  ScoreStatus status = ScoreStatus::Undefined;
  double probability = 0.0;  // of the row's bin; 0 unless OccupiedBin
  double entryLevel = 0.0;   // cumulative probability of the bin; NaN unless OccupiedBin
  std::int64_t rank = -1;    // of the bin in OccupationGrid::bins(); -1 unless OccupiedBin
  bool selected = false;     // the bin is in the contour
};

// Scores of samples (samples[a][i], as for OccupationGrid::fill).
std::vector<RowScore> scoreSamples(const OccupationGrid& grid, const Contour& contour,
                                   const AxisSamples& samples);

// Scores of every row of a catalog holding the columns the grid's axis expressions use. Throws
// ConfigError naming the axis for an unknown column.
std::vector<RowScore> scoreRows(const OccupationGrid& grid, const Contour& contour,
                                const Table& catalog);

}  // namespace octarc
