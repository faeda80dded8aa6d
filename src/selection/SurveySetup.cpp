#include "octarc/selection/SurveySetup.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Segment.h"
#include "octarc/io/FitsTable.h"

namespace octarc {

namespace {

// Appends a warning when both values are known and differ by more than the tolerance.
void compareValue(const char* what, const char* unit, double gridValue, double searchValue,
                  double tolerance, std::vector<std::string>& warnings) {
  if (std::isnan(gridValue) || std::isnan(searchValue)) return;
  const double apart = std::fabs(searchValue - gridValue) / std::fabs(gridValue);
  if (!(apart > tolerance)) return;
  warnings.push_back(std::string(what) + ": made for " + formatNumber(gridValue, "%.6g") + unit +
                     ", the search has " + formatNumber(searchValue, "%.6g") + " (" +
                     formatNumber(100.0 * apart, "%.6g") + "% apart, tolerance " +
                     formatNumber(100.0 * tolerance, "%.6g") + "%)");
}

}  // namespace

std::vector<std::string> compareSetups(const SurveySetup& grid, const SurveySetup& search,
                                       const SetupTolerances& tolerances) {
  std::vector<std::string> warnings;
  compareValue("pixel scale", " arcsec/px", grid.pixelScaleArcsec, search.pixelScaleArcsec,
               tolerances.pixelScale, warnings);
  compareValue("seeing FWHM", " arcsec", grid.seeingFwhmArcsec, search.seeingFwhmArcsec,
               tolerances.seeingFwhm, warnings);
  compareValue("gain", " e-/ADU", grid.gainElectronsPerAdu, search.gainElectronsPerAdu,
               tolerances.gain, warnings);
  compareValue("sky noise", " ADU", grid.skySigmaAdu, search.skySigmaAdu, tolerances.skySigma,
               warnings);
  if (grid.minAreaPix > 0 && search.minAreaPix > 0 && grid.minAreaPix != search.minAreaPix) {
    warnings.push_back("DETECT_MINAREA: made for " + std::to_string(grid.minAreaPix) +
                       " pixels, the search has " + std::to_string(search.minAreaPix));
  }
  if (!grid.thresholdsSigma.empty() && !search.thresholdsSigma.empty()) {
    if (grid.thresholdsSigma.size() != search.thresholdsSigma.size()) {
      warnings.push_back("thresholds: made for " + std::to_string(grid.thresholdsSigma.size()) +
                         " levels, the search has " +
                         std::to_string(search.thresholdsSigma.size()));
    } else {
      for (std::size_t i = 0; i < grid.thresholdsSigma.size(); ++i) {
        const std::string what = "threshold " + std::to_string(i + 1);
        compareValue(what.c_str(), " sigma", grid.thresholdsSigma[i], search.thresholdsSigma[i],
                     tolerances.threshold, warnings);
      }
    }
  }
  return warnings;
}

void addSetupKeywords(const SurveySetup& s, std::vector<FitsKeyword>& k) {
  k.push_back(FitsKeyword::real("PIXSCALE", s.pixelScaleArcsec, "Pixel scale (arcsec/px)"));
  k.push_back(FitsKeyword::real("SEEING", s.seeingFwhmArcsec, "Seeing FWHM (arcsec)"));
  k.push_back(FitsKeyword::real("GAIN", s.gainElectronsPerAdu, "Gain (e-/ADU)"));
  k.push_back(FitsKeyword::real("SKYSIGMA", s.skySigmaAdu, "Sky noise per pixel (ADU)"));
  k.push_back(
      FitsKeyword::integer("NTHRESH", std::int64_t(s.thresholdsSigma.size()), "Detection levels"));
  for (std::size_t i = 0; i < s.thresholdsSigma.size(); ++i) {
    k.push_back(FitsKeyword::real("THRESH" + std::to_string(i + 1), s.thresholdsSigma[i],
                                  "Detection level (sky sigma)"));
  }
  k.push_back(FitsKeyword::integer("MINAREA", s.minAreaPix, "DETECT_MINAREA (pixels)"));
  k.push_back(FitsKeyword::text("POPFILE", s.populationFile, "Population relations file"));
  k.push_back(FitsKeyword::unsignedInteger("SEED", s.seed, "Master seed of the simulations"));
  k.push_back(FitsKeyword::integer("NSYSTEMS", s.systems, "Simulated systems"));
}

namespace {

// The values a setup card may hold. Undefined (NaN) is an unknown value; a gain of 0 is an
// infinite one, as in SExtractor.
bool unknownOrPositive(double v) {
  return std::isnan(v) || (std::isfinite(v) && v > 0.0);
}
bool unknownOrNonNegative(double v) {
  return std::isnan(v) || (std::isfinite(v) && v >= 0.0);
}
bool finitePositive(double v) {
  return std::isfinite(v) && v > 0.0;
}
constexpr const char* kUnknownOrPositive = "undefined (unknown) or a finite number > 0";
static_assert(kMaxSetupLevels <= kMaxThresholdLevels);

}  // namespace

SurveySetup readSetup(const FitsTable& t) {
  SurveySetup s;
  s.pixelScaleArcsec = t.number("PIXSCALE", unknownOrPositive, kUnknownOrPositive);
  s.seeingFwhmArcsec = t.number("SEEING", unknownOrPositive, kUnknownOrPositive);
  s.gainElectronsPerAdu = t.number("GAIN", unknownOrNonNegative,
                                   "undefined (unknown) or a finite number >= 0 (0: infinite)");
  s.skySigmaAdu = t.number("SKYSIGMA", unknownOrPositive, kUnknownOrPositive);
  const std::int64_t levels = t.integer("NTHRESH", 0, kMaxSetupLevels);  // 0: unknown
  for (std::int64_t i = 1; i <= levels; ++i) {
    const std::string key = "THRESH" + std::to_string(i);
    const double level = t.number(key, finitePositive, "a finite number > 0");
    // The detector takes the levels strictly increasing, lowest first.
    if (i > 1 && !(level > s.thresholdsSigma.back())) {
      throw IoError(t.where() + ": " + key + " = " + formatNumber(level, "%.17g") +
                    " is not above THRESH" + std::to_string(i - 1) + " = " +
                    formatNumber(s.thresholdsSigma.back(), "%.17g") +
                    " (the levels increase strictly)");
    }
    s.thresholdsSigma.push_back(level);
  }
  s.minAreaPix = int(t.integer("MINAREA", 0, std::numeric_limits<int>::max()));  // 0: unknown
  s.populationFile = t.text("POPFILE");
  s.seed = t.unsignedInteger("SEED");
  s.systems = t.integer("NSYSTEMS", 0, std::numeric_limits<std::int64_t>::max());
  return s;
}

}  // namespace octarc
