// The settings of a lens-simulation run as a user gives them (command-line options, or a
// caller's own values) and the SimulationSetup they make: Deep Lens Survey defaults, then a
// survey .sex file, then these values; every value checked, with a message that names the option
// (and its .sex key where there is one).
#pragma once

#include <optional>
#include <string>

#include "octarc/simulation/engine/LensSimulation.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

struct LensSetupOptions {
  std::optional<SurveySettings> survey;                  // --config
  std::optional<double> pixelScaleArcsec;                // --pixel-scale (default 0.257)
  std::optional<double> seeingFwhmArcsec;                // --seeing (0.9)
  std::optional<double> gainElectronPerAdu;              // --gain (54)
  std::optional<double> magZeropoint;                    // --zero-point (30)
  std::optional<double> skySigmaAdu;                     // --sky-sigma (default: from limitingMag)
  double limitingMag = 26.0;                             // --limiting-mag: 5 sigma in a 2" aperture
  int stampSizePix = 101;                                // --stamp-size
  std::optional<double> detectThreshold;                 // --thresh (2.5 sigma)
  std::optional<double> detectThresholdMax;              // --thresh-max (20 sigma)
  std::optional<int> detectLevelCount;                   // --nlevels (15)
  std::optional<int> minAreaPix;                         // --minarea (5)
  std::string populationPath;                            // --population ("" = the preset's file)
  std::string populationPreset;                          // --preset: physical (default), dls
  std::optional<double> lensMagMin, lensMagMax;          // --lens-mag-min/max
  std::optional<double> sourceMagMin, sourceMagMax;      // --source-mag-min/max
  std::optional<double> sigmaMinKmPerS, sigmaMaxKmPerS;  // --sigma-min/max
  double lensEllipticityMax = 0.5;                       // --lens-e-max
  double lensHalfLightMinArcsec = 0.5, lensHalfLightMaxArcsec = 1.5;  // --lens-rhalf-min/max
  double fineScaleArcsec = 0.03;  // --fine-scale: ray-tracing grid step
  int subSamples = 4;             // --subsamples: rays per fine pixel along each axis
  // --max-source-step: adaptive sub-sampling (simulation/RayTracer.h), source pixels; 0: every
  // fine pixel gets subSamples^2 rays.
  double maxSourceStepPixels = 1.0;
  // --sampling: which drawn systems are rendered (LensSimulation.h). Plain here, so that a
  // caller that sets nothing renders every system; simulate lenses defaults to importance.
  Sampling sampling = Sampling::Plain;
  // --band NAME: a second band (SecondBand); --source-colour and --lens-colour MEAN,SCATTER
  // need it (their defaults are SecondBand's).
  std::optional<std::string> bandName;
  std::optional<ColourDraw> sourceColour, lensColour;
};

// The run's setup; ConfigError naming the option for a value out of range.
SimulationSetup makeSimulationSetup(const LensSetupOptions& options);

// "MEAN,SCATTER" (mag) as a ColourDraw; ConfigError naming `option` unless both are finite
// numbers and SCATTER >= 0.
ColourDraw parseColourDraw(const std::string& text, const std::string& option);

// --sampling: "importance" or "plain"; ConfigError otherwise.
Sampling parseSampling(const std::string& text);

// The source galaxies: the RealGalaxyCatalog at `realGalaxyCatalogPath`, or (when it is empty)
// `syntheticCount` synthetic galaxies whose stamps reach `extentHalfLightRadii` half-light
// radii, drawn from their own seed stream so that the same sources serve every master seed.
// ConfigError for an extent that is not positive.
SourceDatabase makeSourceDatabase(const std::string& realGalaxyCatalogPath, int syntheticCount,
                                  double extentHalfLightRadii);

}  // namespace octarc
