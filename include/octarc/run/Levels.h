// The detection levels of a run: DETECT_LEVELS, or DETECT_NLEVELS thresholds spaced
// logarithmically from DETECT_THRESH to DETECT_THRESH_MAX, in THRESH_TYPE units, and the same
// in ADU once the noise sigma is known.
#pragma once

#include <vector>

#include "octarc/core/Segment.h"
#include "octarc/run/RunSettings.h"

namespace octarc {

// Converts a threshold in THRESH_TYPE units to ADU (RELATIVE: multiples of sigma).
double thresholdToAdu(double value, bool relative, double sigmaAdu);

// `count` thresholds spaced logarithmically from `low` to `high` (both included), lowest first;
// `count` 1 gives {low}. ConfigError unless 0 < low < high when count > 1.
std::vector<double> logSpacedLevels(double low, double high, int count);

// The levels as the configuration gives them, in THRESH_TYPE units, lowest first.
std::vector<double> levelValues(const RunSettings& settings);

// The detection levels in ADU for a global noise of `sigmaAdu`, lowest first. One level is a
// plain SExtractor run with its own ANALYSIS_THRESH; with several, each level's isophote is its
// detection threshold. ConfigError when the levels do not increase strictly or one is not a
// positive number of ADU. (With sigmaAdu 1 it checks the list before any image is read.)
// Dual-image mode: `measurementSigmaAdu` > 0 is the measurement image's noise, in which the
// analysis thresholds (the isophotes of ISOAREA_IMAGE) are counted, as in SExtractor.
std::vector<ThresholdLevel> detectionLevels(const RunSettings& settings, double sigmaAdu,
                                            double measurementSigmaAdu = 0.0);

// Levels 1..n at `thresholdsAdu` (increasing), each its own analysis threshold: the levels of
// an image whose noise sigma is known in advance (simulations).
std::vector<ThresholdLevel> levelsAtThresholds(const std::vector<double>& thresholdsAdu,
                                               double sigmaAdu);

}  // namespace octarc
