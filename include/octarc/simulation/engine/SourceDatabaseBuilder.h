// A source-galaxy database cut out of a deep image (the engine of `octarc simulate database`):
// SExtractor's mesh background, one detection level at k sigma, and per object a clean,
// noise-free stamp of its footprint (simulation/GalaxyCutout.h), written in GalSim's
// RealGalaxyCatalog format for `octarc simulate lenses --database`.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Progress.h"
#include "octarc/simulation/GalaxyCutout.h"
#include "octarc/simulation/RealGalaxyCatalogWriter.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

struct SourceDatabaseSettings {
  std::string imagePath;
  double thresholdSigma = 4.0;             // the paper's 4 sigma
  std::optional<int> minAreaPixels;        // DETECT_MINAREA (default: the survey's, else 5)
  int minSizePixels = 25;                  // smaller footprints are barely resolved
  int marginPixels = 4;                    // zero pixels around the footprint in each stamp
  std::optional<double> pixelScaleArcsec;  // default: the survey's, the WCS, header keywords
  std::optional<std::string> band;         // default: the FILTER header keyword, else UNKNOWN
  std::optional<double> zeroPointMag;      // default: the survey's, header keywords, else 0
  std::optional<double> saturationAdu;     // default: the survey's, SATURATE, else none
  std::optional<double> psfFwhmArcsec;     // also write a Gaussian PSF of this FWHM
  std::int64_t maxGalaxies = 0;            // keep the N brightest; 0: all
  std::optional<SurveySettings> survey;    // --config
};

// A value with where it came from, for the summary.
template <typename T>
struct Sourced {
  T value{};
  std::string origin;
};

struct SourceDatabaseBuild {
  std::vector<simulation::RealGalaxyRecord> records;  // kept galaxies, in IDENT order
  std::map<simulation::CutoutVerdict, std::int64_t> verdicts;
  std::int64_t objectCount = 0;  // objects above the threshold
  double sigmaAdu = 0.0;         // background sigma
  std::int64_t widthPix = 0, heightPix = 0;
  Sourced<double> pixelScale, zeroPoint;
  std::string band;
  std::vector<std::string> warnings;  // header values ignored, ...
};

// Cuts the galaxies of settings.imagePath; `progress` gets the objects done. ConfigError when
// no galaxy is kept (the message says why each object was skipped).
SourceDatabaseBuild buildSourceDatabase(const SourceDatabaseSettings& settings,
                                        const ProgressFn& progress);

// Writes the database as a RealGalaxyCatalog at `outputPath` (with HISTORY cards naming
// `version`, the threshold and the source image).
simulation::RealGalaxyCatalogPaths writeSourceDatabase(const std::string& outputPath,
                                                       const SourceDatabaseBuild& build,
                                                       const SourceDatabaseSettings& settings,
                                                       const char* version);

// ConfigError when a file of the database at `outputPath` would overwrite the image it is cut
// from, or when its directory does not exist.
void checkSourceDatabaseOutputs(const std::string& outputPath,
                                const SourceDatabaseSettings& settings);

// The run's summary: galaxies kept of the objects above the threshold, why the others were
// skipped, the pixel scale and zero point and where they came from, the files `written`, the
// time taken.
std::string sourceDatabaseSummary(const SourceDatabaseBuild& build,
                                  const SourceDatabaseSettings& settings,
                                  const simulation::RealGalaxyCatalogPaths& written,
                                  double seconds);

}  // namespace octarc
