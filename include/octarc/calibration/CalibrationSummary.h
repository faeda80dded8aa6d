// What `octarc calibrate` prints when it is done: the lensing fractions, the Gaussian fits of
// the distributions, the noise-only threshold, the threshold-count curve, the S/N floor, the
// colour cut and the occupation grid, as far as the run made them.
#pragma once

#include "octarc/calibration/Calibration.h"
#include "octarc/calibration/CalibrationKeys.h"

namespace octarc {

// On stdout (the S/N floor's table through std::cout, flushed in order with the rest).
void printCalibrationSummary(const CalibrationRun& run, const CalibrationResult& result);

}  // namespace octarc
