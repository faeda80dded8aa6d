#include "octarc/run/Levels.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "octarc/core/Error.h"

namespace octarc {

double thresholdToAdu(double value, bool relative, double sigmaAdu) {
  return relative ? value * sigmaAdu : value;
}

std::vector<double> logSpacedLevels(double low, double high, int count) {
  if (count < 1) throw ConfigError("DETECT_NLEVELS must be at least 1");
  if (count == 1) return {low};
  if (!(low > 0) || !(high > low)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "DETECT_THRESH_MAX (%g) must be above DETECT_THRESH (%g), both positive, for "
                  "several levels",
                  high, low);
    throw ConfigError(text);
  }
  std::vector<double> levels;
  for (int k = 0; k < count; ++k) {
    levels.push_back(low * std::pow(high / low, double(k) / double(count - 1)));
  }
  return levels;
}

std::vector<double> levelValues(const RunSettings& s) {
  if (!s.detectLevels.empty()) return s.detectLevels;
  return logSpacedLevels(s.detectThreshold, s.detectThresholdMax, s.detectLevelCount);
}

std::vector<ThresholdLevel> detectionLevels(const RunSettings& s, double sigmaAdu,
                                            double measurementSigmaAdu) {
  const bool relative = s.detectThresholdType == ThresholdType::Relative;
  const double analysisSigmaAdu = measurementSigmaAdu > 0 ? measurementSigmaAdu : sigmaAdu;
  const std::vector<double> values = levelValues(s);
  std::vector<ThresholdLevel> levels;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0 && !(values[k] > values[k - 1])) {
      char text[96];
      std::snprintf(text, sizeof text, "DETECT_LEVELS: levels must increase strictly (%g then %g)",
                    values[k - 1], values[k]);
      throw ConfigError(text);
    }
    ThresholdLevel l;
    l.level = int(k) + 1;
    l.thresholdAdu = thresholdToAdu(values[k], relative, sigmaAdu);
    l.analysisThresholdAdu =
        values.size() == 1
            ? thresholdToAdu(s.analysisThreshold,
                             s.analysisThresholdType == ThresholdType::Relative, analysisSigmaAdu)
            : thresholdToAdu(values[k], relative, analysisSigmaAdu);
    l.thresholdSigma = sigmaAdu > 0 ? l.thresholdAdu / sigmaAdu : std::nan("");
    if (!(l.thresholdAdu > 0) || !std::isfinite(l.thresholdAdu)) {
      throw ConfigError("detection threshold of level " + std::to_string(l.level) + " is " +
                        std::to_string(l.thresholdAdu) + " ADU: it must be positive");
    }
    levels.push_back(l);
  }
  return levels;
}

std::vector<ThresholdLevel> levelsAtThresholds(const std::vector<double>& thresholdsAdu,
                                               double sigmaAdu) {
  std::vector<ThresholdLevel> levels;
  for (std::size_t k = 0; k < thresholdsAdu.size(); ++k) {
    ThresholdLevel l;
    l.level = int(k) + 1;
    l.thresholdAdu = thresholdsAdu[k];
    l.analysisThresholdAdu = l.thresholdAdu;
    l.thresholdSigma = l.thresholdAdu / sigmaAdu;
    levels.push_back(l);
  }
  return levels;
}

}  // namespace octarc
