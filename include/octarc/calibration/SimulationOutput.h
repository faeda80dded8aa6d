// The output of `octarc simulate lenses` as `octarc calibrate` reads it: the systems table
// (LDAC_OBJECTS: truth, ARC_FOUND and the chosen arc's measurements), the arc table (ARCS: every
// arc row at every qualifying level) and the survey setup of its OCT* header cards.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/selection/SurveySetup.h"
#include "octarc/simulation/engine/LensSetup.h"

namespace octarc {

struct SimulationOutput {
  std::string path;  // or the paths joined by "," for combined outputs
  Table systems;     // one row per simulated system
  Table arcs;        // one row per arc row
  SurveySetup setup;
  double magZeropoint = 0.0;   // OCTMAGZP
  std::string sourceDatabase;  // OCTSRCDB: "synthetic (N galaxies)" or a catalog path
  std::string populationName;  // OCTPOPUL: the population file's name without ".txt"
};

// The source galaxies of a run to remake: a RealGalaxyCatalog, or the synthetic generator as
// simulate lenses makes it (its own seed stream, kSyntheticSourceSeed).
struct SourceChoice {
  std::string catalogPath;                     // "": the synthetic sources
  int syntheticCount = 90;                     // --sources
  double syntheticExtentHalfLightRadii = 4.0;  // --source-extent (not recorded in the output)
  SourceDatabase make() const;
};

// Reads a simulate-lenses output. IoError naming the file when it is not one (no LDAC_OBJECTS
// with SYSTEM and ARC_FOUND, no ARCS table, no OCTNSYS card) or holds no system.
SimulationOutput readSimulationOutput(const std::string& path);

// Several outputs as one: rows appended in order. ConfigError when their survey setups differ
// (selection/SurveySetup.h, compareSetups), their columns do, or two have the same seed (the
// same systems); the seed of the first is kept and the systems added up.
SimulationOutput combineSimulationOutputs(std::vector<SimulationOutput> outputs);

// The lens-simulation options that remake the survey of `simulation` (pixel scale, seeing, gain,
// zero point, sky noise, the lowest and highest level, DETECT_MINAREA) and its population preset
// (OCTPOPUL): what studies that rerun the simulations start from. The magnitude and sigma_v
// windows, the lens light ranges and the ray tracing are simulate lenses' defaults (the header
// does not record them; checkRemade() catches a simulation made otherwise). ConfigError when
// the population was not a shipped preset.
LensSetupOptions resimulationOptions(const SimulationOutput& simulation);
// The sources of `simulation` (OCTSRCDB).
SourceChoice resimulationSources(const SimulationOutput& simulation);

// Draws the first `systems` systems of `simulation` again with `options` and `sources` and
// compares their Einstein radii with the simulation's; ConfigError naming the file when one
// differs (the simulation was made with options the header does not record).
void checkRemade(const SimulationOutput& simulation, const LensSetupOptions& options,
                 const SourceDatabase& sources, int systems = 20);

}  // namespace octarc
