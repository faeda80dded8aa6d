// The simulation setup and source database the engine's tests share: the dls population, sky
// noise of 1 ADU and 15 thresholds from 2.5 to 20 ADU, and six synthetic galaxies from seed 42.
#pragma once

#include <cmath>

#include "octarc/simulation/Population.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc::test {

inline SimulationSetup engineTestSetup() {
  SimulationSetup setup;
  setup.population = simulation::readPopulationModel(simulation::populationPresetPath("dls"));
  setup.observing.skySigmaAdu = 1.0;
  for (int k = 0; k < 15; ++k) setup.thresholdsAdu.push_back(2.5 * std::pow(8.0, k / 14.0));
  return setup;
}

inline SourceDatabase engineTestSources() {
  simulation::SyntheticGalaxyOptions options;
  options.stampHalfLightRadii = 4.0;
  return SourceDatabase::synthetic(6, 42, options);
}

}  // namespace octarc::test
