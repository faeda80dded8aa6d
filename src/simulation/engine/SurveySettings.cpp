#include "octarc/simulation/engine/SurveySettings.h"

#include "octarc/core/DataFiles.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunKeys.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/ConvFile.h"

namespace octarc {

SurveySettings readSurveySettings(const std::string& configPath) {
  SurveySettings out;
  // As octarc search -c: a name without a directory may be a shipped file (octarc.sex).
  out.configPath = existingUserOrDataFile(configPath, "configuration file");
  const sexcompat::Config config =
      sexcompat::Config::load(octarcKeys(), out.configPath, {}, &out.warnings);
  const RunSettings s = settingsFromConfig(config);
  auto given = [&config](const char* key) { return config.isExplicit(key); };
  if (given("PIXEL_SCALE") && s.pixelScaleArcsec > 0) out.pixelScaleArcsec = s.pixelScaleArcsec;
  if (given("SEEING_FWHM")) out.seeingFwhmArcsec = s.seeingFwhmArcsec;
  if (given("GAIN")) out.gainElectronPerAdu = s.gainElectronPerAdu;
  if (given("MAG_ZEROPOINT")) out.magZeropoint = s.magZeropoint;
  if (given("SATUR_LEVEL")) out.saturationAdu = s.saturationAdu;
  if (given("DETECT_THRESH")) out.detectThreshold = s.detectThreshold;
  if (given("DETECT_THRESH_MAX")) out.detectThresholdMax = s.detectThresholdMax;
  if (given("DETECT_NLEVELS")) out.detectLevelCount = s.detectLevelCount;
  out.detectLevels = s.detectLevels;
  out.relativeLevels = s.detectThresholdType == ThresholdType::Relative;
  if (given("DETECT_MINAREA")) out.minAreaPix = s.minAreaPix;
  if (s.filter) out.filter = sexcompat::readConvFile(resolveFilterFile(s.filterPath));
  if (given("BACK_SIZE")) {
    out.backMeshWidthPix = s.backMeshWidthPix;
    out.backMeshHeightPix = s.backMeshHeightPix;
  }
  if (given("BACK_FILTERSIZE")) {
    out.backFilterWidth = s.backFilterWidth;
    out.backFilterHeight = s.backFilterHeight;
  }
  if (given("BACK_FILTTHRESH")) out.backFilterThresholdAdu = s.backFilterThresholdAdu;
  return out;
}

}  // namespace octarc
