// The lowest detection threshold at which pure survey noise yields no object (METHOD.md
// section 3): images of white Gaussian noise of sigma 1 (the unit of RELATIVE thresholds: the
// background RMS of the unfiltered image), filtered with the survey's detection filter, detected
// at a ladder of thresholds; the noise-only threshold is the lowest rung at which none of the
// realisations gives an object of DETECT_MINAREA pixels or more.
//
// Each realisation has its own random stream (seed, index), so the result does not depend on
// the number of threads. Without a filter and with DETECT_MINAREA 1 an object above t exists
// when the largest pixel exceeds t, so over R realisations of N pixels the threshold T is the
// first rung at or above the largest of R N standard normal values: P(T <= t) = Phi(t)^(R N).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "octarc/core/ConvKernel.h"

namespace octarc {

struct NoiseThresholdSettings {
  int sizePix = 512;  // side of each noise image
  int realisations = 100;
  int minAreaPix = 5;                // DETECT_MINAREA
  std::optional<ConvKernel> filter;  // the survey's detection filter (FILTER Y)
  double loSigma = 0.5, hiSigma = 8.0, stepSigma = 0.03;  // 251 rungs: one detection pass
  std::uint64_t seed = 1;
  int threads = 0;  // 0 = all cores
};

struct NoiseThresholdResult {
  std::vector<double> thresholdsSigma;                // the ladder, lowest first
  std::vector<std::int64_t> realisationsWithObjects;  // per rung
  std::vector<double> meanObjects;                    // per rung, over the realisations
  // The lowest rung with no object in any realisation; NaN when even the highest rung has one.
  double noiseOnlyThresholdSigma = 0.0;
  // True when even the lowest rung gave no object: the threshold is at or below it.
  bool atLowestRung = false;
};

// ConfigError for settings out of range (size < 16, realisations < 1, MINAREA < 1, an empty
// ladder or one of more than 100000 rungs).
NoiseThresholdResult noiseOnlyThreshold(const NoiseThresholdSettings& settings);
// The same checks alone.
void checkNoiseThresholdSettings(const NoiseThresholdSettings& settings);

}  // namespace octarc
