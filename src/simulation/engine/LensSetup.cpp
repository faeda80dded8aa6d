#include "octarc/simulation/engine/LensSetup.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/measure/Colour.h"
#include "octarc/run/Levels.h"
#include "octarc/simulation/Noise.h"
#include "octarc/simulation/SyntheticGalaxy.h"

namespace octarc {

namespace sim = octarc::simulation;

namespace {

void requireRange(double lo, double hi, const char* loName, const char* hiName) {
  if (!(lo < hi)) {
    std::ostringstream s;
    s << loName << " (" << lo << ") must be below " << hiName << " (" << hi << ")";
    throw ConfigError(s.str());
  }
}

// The stamp: grid, PSF, gain, zero point, noise, ray tracing.
void setObserving(const LensSetupOptions& o, SimulationSetup& setup) {
  sim::ObservingSetup& obs = setup.observing;
  if (o.survey) {
    obs.grid.pixelScaleArcsec = o.survey->pixelScaleArcsec.value_or(obs.grid.pixelScaleArcsec);
    obs.seeingFwhmArcsec = o.survey->seeingFwhmArcsec.value_or(obs.seeingFwhmArcsec);
    obs.gainElectronsPerAdu = o.survey->gainElectronPerAdu.value_or(obs.gainElectronsPerAdu);
    obs.magZeroPoint = o.survey->magZeropoint.value_or(obs.magZeroPoint);
    setup.saturationAdu = o.survey->saturationAdu.value_or(setup.saturationAdu);
    setup.filter = o.survey->filter;
  }
  obs.grid.pixelScaleArcsec = o.pixelScaleArcsec.value_or(obs.grid.pixelScaleArcsec);
  obs.seeingFwhmArcsec = o.seeingFwhmArcsec.value_or(obs.seeingFwhmArcsec);
  obs.gainElectronsPerAdu = o.gainElectronPerAdu.value_or(obs.gainElectronsPerAdu);
  obs.magZeroPoint = o.magZeropoint.value_or(obs.magZeroPoint);
  if (!(obs.grid.pixelScaleArcsec > 0)) throw ConfigError("--pixel-scale must be positive");
  if (!(obs.seeingFwhmArcsec > 0)) throw ConfigError("--seeing (SEEING_FWHM) must be positive");
  if (!(obs.gainElectronsPerAdu > 0)) {
    throw ConfigError("--gain (GAIN) must be positive: Poisson noise needs a finite gain");
  }
  if (o.stampSizePix < 9) throw ConfigError("--stamp-size must be at least 9 pixels");
  obs.grid.width = obs.grid.height = o.stampSizePix;
  obs.grid.lensXPix = obs.grid.lensYPix = 0.5 * (o.stampSizePix - 1);
  obs.skySigmaAdu = o.skySigmaAdu
                        ? *o.skySigmaAdu
                        : sim::skySigmaFromLimitingMagnitude(o.limitingMag, obs.magZeroPoint, 2.0,
                                                             obs.grid.pixelScaleArcsec);
  if (!(obs.skySigmaAdu > 0)) throw ConfigError("--sky-sigma must be positive");
  obs.rayTrace.fineScaleArcsec = o.fineScaleArcsec;
  obs.rayTrace.subSamples = o.subSamples;
  obs.rayTrace.maxSourceStepPixels = o.maxSourceStepPixels;
  if (!(o.maxSourceStepPixels >= 0)) throw ConfigError("--max-source-step must be >= 0");
  setup.sampling = o.sampling;
  if (!(obs.rayTrace.fineScaleArcsec > 0)) throw ConfigError("--fine-scale must be positive");
  if (obs.rayTrace.subSamples < 1) throw ConfigError("--subsamples must be at least 1");
}

// Levels: the same log spacing as octarc detect (DETECT_NLEVELS from DETECT_THRESH to
// DETECT_THRESH_MAX); RELATIVE levels are multiples of the stamp's known sky sigma.
void setLevels(const LensSetupOptions& o, SimulationSetup& setup) {
  double threshLow = 2.5, threshHigh = 20.0;
  int levelCount = 15, minArea = 5;
  std::vector<double> levels;
  bool relative = true;
  if (o.survey) {
    threshLow = o.survey->detectThreshold.value_or(threshLow);
    threshHigh = o.survey->detectThresholdMax.value_or(threshHigh);
    levelCount = o.survey->detectLevelCount.value_or(levelCount);
    levels = o.survey->detectLevels;
    relative = o.survey->relativeLevels;
    minArea = o.survey->minAreaPix.value_or(minArea);
  }
  // A level option replaces the .sex file's explicit list.
  if (o.detectThreshold || o.detectThresholdMax || o.detectLevelCount) levels.clear();
  threshLow = o.detectThreshold.value_or(threshLow);
  threshHigh = o.detectThresholdMax.value_or(threshHigh);
  levelCount = o.detectLevelCount.value_or(levelCount);
  minArea = o.minAreaPix.value_or(minArea);
  if (minArea < 1) throw ConfigError("--minarea (DETECT_MINAREA) must be at least 1");
  if (levels.empty()) {
    if (levelCount < 1) throw ConfigError("--nlevels (DETECT_NLEVELS) must be at least 1");
    if (levelCount > 1) {
      requireRange(threshLow, threshHigh, "--thresh (DETECT_THRESH)",
                   "--thresh-max (DETECT_THRESH_MAX)");
    }
    levels = logSpacedLevels(threshLow, threshHigh, levelCount);
  }
  for (double l : levels) {
    const double adu = relative ? l * setup.observing.skySigmaAdu : l;
    if (!(adu > 0)) throw ConfigError("detection thresholds must be positive");
    setup.thresholdsAdu.push_back(adu);
    setup.thresholdsSigma.push_back(relative ? l : l / setup.observing.skySigmaAdu);
  }
  setup.minAreaPix = minArea;
}

// Population: the relations file, then the range options; the lens light.
void setPopulation(const LensSetupOptions& o, SimulationSetup& setup) {
  if (!o.populationPath.empty() && !o.populationPreset.empty())
    throw ConfigError("--population and --preset both name a population file: give one");
  // A file of one's own has no preset name; otherwise the preset, "physical" by default.
  setup.populationPreset = !o.populationPath.empty()    ? ""
                           : o.populationPreset.empty() ? "physical"
                                                        : o.populationPreset;
  setup.population = sim::readPopulationModel(
      setup.populationPreset.empty() ? o.populationPath
                                     : sim::populationPresetPath(setup.populationPreset));
  sim::PopulationModel& pop = setup.population;
  pop.tabulate(setup.cosmology);
  pop.lensMagMin = o.lensMagMin.value_or(pop.lensMagMin);
  pop.lensMagMax = o.lensMagMax.value_or(pop.lensMagMax);
  pop.sourceMagnitude.magMin = o.sourceMagMin.value_or(pop.sourceMagnitude.magMin);
  pop.sourceMagnitude.magMax = o.sourceMagMax.value_or(pop.sourceMagnitude.magMax);
  pop.sigmaMinKmPerS = o.sigmaMinKmPerS.value_or(pop.sigmaMinKmPerS);
  pop.sigmaMaxKmPerS = o.sigmaMaxKmPerS.value_or(pop.sigmaMaxKmPerS);
  requireRange(pop.lensMagMin, pop.lensMagMax, "--lens-mag-min", "--lens-mag-max");
  requireRange(pop.sourceMagnitude.magMin, pop.sourceMagnitude.magMax, "--source-mag-min",
               "--source-mag-max");
  requireRange(pop.sigmaMinKmPerS, pop.sigmaMaxKmPerS, "--sigma-min", "--sigma-max");
  setup.lensEllipticityMax = o.lensEllipticityMax;
  if (!(setup.lensEllipticityMax >= 0 && setup.lensEllipticityMax < 1)) {
    throw ConfigError("--lens-e-max must be in [0, 1)");
  }
  setup.lensHalfLightMinArcsec = o.lensHalfLightMinArcsec;
  setup.lensHalfLightMaxArcsec = o.lensHalfLightMaxArcsec;
  if (!(setup.lensHalfLightMinArcsec > 0)) throw ConfigError("--lens-rhalf-min must be positive");
  requireRange(setup.lensHalfLightMinArcsec, setup.lensHalfLightMaxArcsec, "--lens-rhalf-min",
               "--lens-rhalf-max");
}

void checkColour(const ColourDraw& c, const char* option) {
  if (!std::isfinite(c.meanMag) || !std::isfinite(c.scatterMag) || c.scatterMag < 0) {
    throw ConfigError(std::string(option) +
                      ": the mean must be a number and the scatter a number >= 0 (mag)");
  }
}

// The second band: a name fit for column names, and its colours.
void setBand(const LensSetupOptions& o, SimulationSetup& setup) {
  if (!o.bandName) {
    if (o.sourceColour || o.lensColour) {
      throw ConfigError(std::string(o.sourceColour ? "--source-colour" : "--lens-colour") +
                        " needs --band NAME (the band the colour is for)");
    }
    return;
  }
  if (!isBandName(*o.bandName)) {
    throw ConfigError("--band: '" + *o.bandName +
                      "' is not a band name for column names (1-16 letters, digits or _)");
  }
  SecondBand band;
  band.name = *o.bandName;
  band.source = o.sourceColour.value_or(band.source);
  band.lens = o.lensColour.value_or(band.lens);
  checkColour(band.source, "--source-colour");
  checkColour(band.lens, "--lens-colour");
  setup.band = band;
}

}  // namespace

SimulationSetup makeSimulationSetup(const LensSetupOptions& options) {
  SimulationSetup setup;
  setObserving(options, setup);
  setLevels(options, setup);
  setPopulation(options, setup);
  setBand(options, setup);
  return setup;
}

ColourDraw parseColourDraw(const std::string& text, const std::string& option) {
  const std::size_t comma = text.find(',');
  auto number = [](const std::string& word, double* value) {
    char* end = nullptr;
    *value = std::strtod(word.c_str(), &end);
    return !word.empty() && end == word.c_str() + word.size() && std::isfinite(*value);
  };
  ColourDraw c;
  if (comma == std::string::npos || !number(text.substr(0, comma), &c.meanMag) ||
      !number(text.substr(comma + 1), &c.scatterMag)) {
    throw ConfigError(option + ": give MEAN,SCATTER in mag, e.g. " + option + " 0.4,0.3 (got '" +
                      text + "')");
  }
  if (c.scatterMag < 0) {
    throw ConfigError(option + ": the scatter must be >= 0 (got '" + text + "')");
  }
  return c;
}

Sampling parseSampling(const std::string& text) {
  if (text == "importance") return Sampling::Importance;
  if (text == "plain") return Sampling::Plain;
  throw ConfigError("--sampling: '" + text + "' is neither importance nor plain");
}

SourceDatabase makeSourceDatabase(const std::string& realGalaxyCatalogPath, int syntheticCount,
                                  double extentHalfLightRadii) {
  if (!realGalaxyCatalogPath.empty()) {
    return SourceDatabase::fromRealGalaxyCatalog(realGalaxyCatalogPath);
  }
  sim::SyntheticGalaxyOptions galaxy;
  galaxy.stampHalfLightRadii = extentHalfLightRadii;
  if (!(galaxy.stampHalfLightRadii > 0)) throw ConfigError("--source-extent must be positive");
  return SourceDatabase::synthetic(syntheticCount, kSyntheticSourceSeed, galaxy);
}

}  // namespace octarc
