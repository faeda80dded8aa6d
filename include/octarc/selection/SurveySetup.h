// The survey setup an occupation grid was made for: a grid is reusable across surveys of the
// same depth and seeing (METHOD.md section 4), so a search on another setup is warned.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "octarc/io/FitsTable.h"

namespace octarc {

// NaN, 0 or empty for what is not known; unknown fields are never compared.
struct SurveySetup {
  double pixelScaleArcsec = std::numeric_limits<double>::quiet_NaN();
  double seeingFwhmArcsec = std::numeric_limits<double>::quiet_NaN();
  double gainElectronsPerAdu = std::numeric_limits<double>::quiet_NaN();
  double skySigmaAdu = std::numeric_limits<double>::quiet_NaN();  // per-pixel sky noise
  std::vector<double> thresholdsSigma;  // detection levels in units of the sky sigma, lowest first
  int minAreaPix = 0;                   // DETECT_MINAREA
  // Provenance of the simulations (not compared: a survey has none of them).
  std::string populationFile;
  std::uint64_t seed = 0;
  std::int64_t systems = 0;  // simulated systems
};

// Relative differences beyond which a search's setup is warned about. The defaults: the pixel
// scale and the thresholds are configuration choices, equal in practice (1%); seeing, gain and
// sky noise vary from field to field, and 10% in noise is about 0.1 mag in depth.
struct SetupTolerances {
  double pixelScale = 0.01;
  double seeingFwhm = 0.10;
  double gain = 0.10;
  double skySigma = 0.10;
  double threshold = 0.01;
};

// One line per difference between the setup a grid was made for and the setup of a search,
// e.g. "seeing FWHM: made for 0.9 arcsec, the search has 1.2 (33% apart,
// tolerance 10%)"; empty when they agree. DETECT_MINAREA and the number of thresholds must be
// equal. |a - b| / |a| is compared with the tolerance, a being the grid's value.
std::vector<std::string> compareSetups(const SurveySetup& grid, const SurveySetup& search,
                                       const SetupTolerances& tolerances = {});

// The setup as header keywords of a grid or model file (PIXSCALE, SEEING, GAIN, SKYSIGMA,
// NTHRESH, THRESHn, MINAREA, POPFILE, SEED, NSYSTEMS; NaN as an undefined value), and back
// (IoError naming the table and the keyword when one is missing or out of its range: at most 99
// levels, THRESHn increasing strictly).
void addSetupKeywords(const SurveySetup& setup, std::vector<FitsKeyword>& keywords);
// The most levels a grid or model file records: THRESHnn holds two digits in its 8 characters.
inline constexpr int kMaxSetupLevels = 99;
SurveySetup readSetup(const FitsTable& table);

}  // namespace octarc
