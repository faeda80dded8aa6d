// Which injected lenses of a simulated field came back in a detection run, and with what
// arcness: the truth list of simulateField() matched against the rows of the run. The demo
// reports it; completeness studies and the search's recovery tests build on it.
//
// A row is one of system S's arcs when it is resolved (sqrt(2) SIZE_IMAGE > the arc rules'
// minimum size), at least the rules' minimum distance from S's lens and within `matchArcsec` of
// one of S's lensed images in the truth list (arcs are extended: a piece found at a high level
// can sit well off the image's flux centroid). A resolved row farther than theta_E +
// 2 matchArcsec from every lens counts as an "other object".
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

// The columns the matching reads, each value as a catalog stores it (single-precision columns
// rounded to float), rows in catalog order.
struct RecoveryRows {
  std::vector<double> level, threshold, x, y, arcness, size, snr;  // x, y 1-based pixels
  std::size_t rows() const { return level.size(); }
};

// The rows of `table` (THRESH_LEVEL, THRESHOLD, X_IMAGE, Y_IMAGE, ARCNESS, SIZE_IMAGE,
// SNR_ISO) taken in `order` (empty: as stored). Error when a column is missing.
RecoveryRows recoveryRows(const Table& table, const std::vector<std::int64_t>& order);

struct InjectedSystem {
  double lensXPix = 0, lensYPix = 0;  // 1-based
  double einsteinRadiusArcsec = 0;
  std::vector<std::array<double, 2>> imagesPix;  // lensed images, 1-based
  std::int64_t bestRow = -1;                     // its arc row of largest ARCNESS; -1: not found
};

struct InjectionRecovery {
  std::map<int, std::int64_t> objectsPerLevel;
  std::map<int, double> levelThresholdAdu;
  int levelCount = 0;
  std::map<int, InjectedSystem> systems;  // by system id
  std::vector<double> arcArcness;         // every arc row, every level
  std::vector<double> otherArcness;       // every other resolved row
  std::vector<double> bestArcness;        // per found system, its best arc row
};

InjectionRecovery recoverInjectedArcs(const std::vector<TruthRow>& truth, const RecoveryRows& rows,
                                      double pixelScaleArcsec, const ArcRules& rules,
                                      double matchArcsec);

// The recovery as text: objects and threshold per level, each system's best arc (theta_E,
// ARCNESS, level, S/N or "not found"), and the arcness of arcs against other objects
// (median, fraction above `arcLikeArcness`).
void printRecovery(std::ostream& out, const InjectionRecovery& recovery, const RecoveryRows& rows,
                   const ArcRules& rules, double matchArcsec, double arcLikeArcness);

// The fraction of `values` above `cut` (NaN when empty).
double fractionAbove(const std::vector<double>& values, double cut);

}  // namespace octarc
