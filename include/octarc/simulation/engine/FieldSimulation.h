// A simulated survey field with injected galaxy-galaxy lenses (`octarc simulate field`, also the
// first step of `octarc demo`): the image, its MAP_WEIGHT weight map and a truth list that loads
// as a SExtractor ASSOC list.
//
//   population draws --> per-object stamps (threads) --> sum --> PSF --> stars --> sky noise
//   --> saturation clip --> FIELD.fits, FIELD.weight.fits, FIELD.truth.txt
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Image.h"
#include "octarc/core/Progress.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/io/FitsImage.h"
#include "octarc/simulation/FieldPopulation.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

struct FieldSimulationSettings {
  int sizePix = 4096;               // square field
  double pixelScaleArcsec = 0.257;  // DLS
  double seeingFwhmArcsec = 0.9;    // Gaussian PSF
  double gainElectronsPerAdu = 54.0;
  double magZeroPoint = 30.0;
  std::optional<double> noiseSigmaAdu;  // per-pixel sky noise; else from limitingMag
  double limitingMag = 26.0;            // 5-sigma, in an aperture of diameter 2 x seeing FWHM
  double saturationAdu = 30000.0;
  int lensCount = 0;
  // Lens systems with a smaller Einstein radius are redrawn (0 = the population as it is).
  double minEinsteinRadiusArcsec = 0.0;
  // ... and so are those with a larger one (0 = no upper limit).
  double maxEinsteinRadiusArcsec = 0.0;
  std::uint64_t seed = 1;
  double raDeg = 150.0;  // CRVAL1 / CRVAL2 at the field centre
  double decDeg = 2.0;
  std::string databasePath;    // RealGalaxyCatalog of lensed sources; "" = synthetic sources
  std::string populationPath;  // lens population file; "" = the dls preset (population-dls.txt)
  int threads = 0;             // 0 = all cores; the result does not depend on it
  simulation::FieldPopulationParams population;

  // The per-pixel sky sigma in ADU (noiseSigmaAdu, or from the limiting magnitude).
  double skySigmaAdu() const;
  // Throws ConfigError naming the option ("--size", "--seeing", ...) for a nonsense value.
  void validate() const;
};

// The survey settings of a .sex file (readSurveySettings) over `settings`, those the file
// gives: PIXEL_SCALE, SEEING_FWHM, GAIN (when > 0: GAIN 0, infinite, cannot make Poisson
// noise, so the field keeps its own), MAG_ZEROPOINT, SATUR_LEVEL.
void applySurveySettings(FieldSimulationSettings& settings, const SurveySettings& survey);

// One row of the truth list.
struct TruthRow {
  std::int64_t id = 0;
  double xFits = 0.0, yFits = 0.0;  // 1-based pixel centre
  double raDeg = 0.0, decDeg = 0.0;
  simulation::FieldObjectKind kind = simulation::FieldObjectKind::Galaxy;
  double mag = 0.0;
  double einsteinRadiusArcsec = 0.0;  // lens galaxies and lensed images; 0 otherwise
  int systemId = 0;                   // 1..N for lens systems; 0 otherwise
};

struct SimulatedField {
  ImageF image;   // ADU, sky subtracted
  ImageF weight;  // 1 / variance (ADU^-2); empty for an image injected into without one
  FitsHeader header;
  FitsHeader weightHeader;
  std::vector<TruthRow> truth;  // lens systems first (lens, then its images), galaxies, stars
  double skySigmaAdu = 0.0;
  int gapX0 = 0, gapX1 = 0;  // chip-gap columns [gapX0, gapX1), 0-based: half the exposure
  std::int64_t galaxyCount = 0, starCount = 0, saturatedPixels = 0;
  std::vector<simulation::FieldLens> lenses;  // without their stamps
};

// Simulates the field (settings are validated first). Reproducible from settings.seed whatever
// the thread count.
SimulatedField simulateField(const FieldSimulationSettings& settings,
                             const ProgressFn& progress = {});

// Injects settings.lensCount lens systems into a real image (`octarc demo --into`): the systems
// of simulateField (same draws and rendering, placed at least 30" apart and away from the
// edges), convolved with the Gaussian PSF of settings.seeingFwhmArcsec at
// settings.pixelScaleArcsec, with the photon noise of their own flux (settings gain), added to
// the image's pixels as read (background and all). The image's header and, when given, its
// weight map are kept; the truth list holds the lens systems only (RA, Dec NaN without a
// celestial WCS). ConfigError for a weight map of another size.
SimulatedField injectLenses(const ImageHdu& image, const ImageHdu* weight,
                            const FieldSimulationSettings& settings);

// The three output names of `octarc simulate field -o IMAGE`: IMAGE, IMAGE minus its .fits/.fit
// suffix + ".weight.fits" and + ".truth.txt".
struct FieldOutputPaths {
  std::string image, weight, truth;
  static FieldOutputPaths fromImagePath(const std::string& imagePath);
};

// Adds the image (the main output), the weight map and the truth list to `outputs`, which
// checks them before the simulation starts (so a bad -o costs nothing).
void addFieldOutputs(OutputFiles& outputs, const FieldOutputPaths& paths);

// Writes the image, the weight map and the truth list at the temporary names of outputs
// first, first + 1 and first + 2 (as added by addFieldOutputs); the caller commits the set.
void writeSimulatedField(const SimulatedField& field, const FieldSimulationSettings& settings,
                         const FieldOutputPaths& paths, const OutputFiles& outputs,
                         std::size_t first = 0);

// The truth list's column layout, for ASSOC_PARAMS / ASSOC_DATA: 1-based columns.
constexpr int kTruthColumnId = 1, kTruthColumnX = 2, kTruthColumnY = 3, kTruthColumnKind = 6,
              kTruthColumnMag = 7, kTruthColumnEinsteinRadius = 8, kTruthColumnSystem = 9;

}  // namespace octarc
