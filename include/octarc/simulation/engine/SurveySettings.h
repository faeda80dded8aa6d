// The survey a simulation imitates, read from an octarc .sex file: the one mapping from
// configuration keys to survey settings that `simulate lenses`, `simulate field` and `simulate
// database` share.
//
// Only keys the file sets are taken: SExtractor's own defaults (zero point 0, gain 0 =
// infinite, 1.2" seeing) would describe no survey, so each simulation keeps its own survey
// defaults for the rest.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "octarc/core/ConvKernel.h"

namespace octarc {

struct SurveySettings {
  std::string configPath;
  std::optional<double> pixelScaleArcsec;    // PIXEL_SCALE, when > 0 (0 means "from the WCS")
  std::optional<double> seeingFwhmArcsec;    // SEEING_FWHM
  std::optional<double> gainElectronPerAdu;  // GAIN (0 = infinite: each simulation decides)
  std::optional<double> magZeropoint;        // MAG_ZEROPOINT
  std::optional<double> saturationAdu;       // SATUR_LEVEL
  std::optional<double> detectThreshold;     // DETECT_THRESH
  std::optional<double> detectThresholdMax;  // DETECT_THRESH_MAX
  std::optional<int> detectLevelCount;       // DETECT_NLEVELS
  std::vector<double> detectLevels;          // DETECT_LEVELS (empty when not given)
  bool relativeLevels = true;                // THRESH_TYPE RELATIVE
  std::optional<int> minAreaPix;             // DETECT_MINAREA
  std::optional<ConvKernel> filter;          // FILTER Y: the FILTER_NAME kernel
  // The mesh background: BACK_SIZE, BACK_FILTERSIZE (one value: square), BACK_FILTTHRESH.
  std::optional<int> backMeshWidthPix, backMeshHeightPix;
  std::optional<int> backFilterWidth, backFilterHeight;
  std::optional<double> backFilterThresholdAdu;
  std::vector<std::string> warnings;  // configuration warnings (unknown keys, ...)
};

// Reads `configPath` (SExtractor .sex syntax, octarc's keys; a name without a directory that
// is not in the working directory may be a shipped file, e.g. octarc.sex). ConfigError / IoError
// naming the file for a bad file or value.
SurveySettings readSurveySettings(const std::string& configPath);

}  // namespace octarc
