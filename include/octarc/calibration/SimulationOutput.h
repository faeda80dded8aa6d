// The output of `octarc simulate lenses` as `octarc calibrate` reads it: the systems table
// (LDAC_OBJECTS: truth, ARC_FOUND and the chosen arc's measurements), the arc table (ARCS: every
// arc row at every qualifying level) and the survey setup of its OCT* header cards.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/selection/SurveySetup.h"
#include "octarc/simulation/engine/LensSetup.h"

namespace octarc {

struct SimulationOutput {
  std::string path;  // or the paths joined by "," for combined outputs
  Table systems;     // one row per rendered system (SIM_WEIGHT: the systems it stands for)
  Table arcs;        // one row per arc row
  SurveySetup setup;
  double magZeropoint = 0.0;   // OCTMAGZP
  std::string sourceDatabase;  // OCTSRCDB: "synthetic (N galaxies)" or a catalog path
  std::string band;            // OCTBAND: the second band (simulate lenses --band), "" for none
  FitsHeader header;           // its LDAC_IMHEAD (the run's OCT* cards)
  int outputs = 1;             // how many outputs were combined into this one
  // Where each combined output's rows start in `systems` and in `arcs` (one entry per output;
  // SYSTEM repeats across outputs, so an arc row's system is looked for within its output).
  std::vector<std::int64_t> systemsStart = {0}, arcsStart = {0};
};

// The source galaxies of a run to remake: a RealGalaxyCatalog, or the synthetic generator as
// simulate lenses makes it (its own seed stream, kSyntheticSourceSeed).
struct SourceChoice {
  std::string catalogPath;                     // "": the synthetic sources
  int syntheticCount = 90;                     // --sources
  double syntheticExtentHalfLightRadii = 4.0;  // --source-extent (OCTSRCEX)
  SourceDatabase make() const;
};

// Reads a simulate-lenses output. IoError naming the file when it is not one (no LDAC_OBJECTS
// with SYSTEM and ARC_FOUND, no ARCS table, no OCTNSYS card) or drew no system (OCTNSYS 0; a
// run that drew systems but rendered none is read, with no row). setup.systems is OCTNSYS,
// the systems drawn from the population.
SimulationOutput readSimulationOutput(const std::string& path);

// Several outputs as one: rows appended in order. ConfigError when their survey setups differ
// (selection/SurveySetup.h, compareSetups), their population or sources do (the cards that
// resimulationOptions reads), their columns do, or two have the same seed (the same systems);
// the seed of the first is kept and the systems added up.
SimulationOutput combineSimulationOutputs(std::vector<SimulationOutput> outputs);

// The lens-simulation options that remake the systems of `simulation`, from the cards its run
// recorded: the survey (pixel scale, seeing, gain, zero point, sky noise, the lowest and
// highest level, DETECT_MINAREA), the population preset and its windows (lens and source
// magnitudes, sigma_v), the lens light ranges, the stamp size, the ray tracing and the second
// band with its colours (OCTBAND, OCTSCOLM, OCTSCOLS, OCTLCOLM, OCTLCOLS) when there is one, the
// sampling (OCTSAMPL; plain when absent) and the adaptive ray step (OCTSSTEP; 0 when absent).
// What studies that simulate again start from. ConfigError naming the file when the population
// was a file of one's own (OCTPRSET ''), the output predates these cards, or its importance
// sampling's render probabilities (OCTISSCL, OCTISFLR, OCTISC0..4) are not this octarc's.
LensSetupOptions resimulationOptions(const SimulationOutput& simulation);
// The sources of `simulation` (OCTSRCDB, OCTSRCEX).
SourceChoice resimulationSources(const SimulationOutput& simulation);

// Draws the systems at `rows` of `simulation` (by default its first 20) again with `options`
// and `sources` and compares their Einstein radius, lens half-light radius, source position and
// SIM_WEIGHT with the file's; ConfigError naming the file and the system when one differs or is
// not rendered.
void checkRemade(const SimulationOutput& simulation, const LensSetupOptions& options,
                 const SourceDatabase& sources, std::vector<std::int64_t> rows = {});
// The comparison of one system: ConfigError unless `remade` (drawn again) is rendered and has
// the Einstein radius, lens half-light radius, source position and weight of row `row`.
void requireRemadeDraw(const SimulationOutput& simulation, std::int64_t row,
                       const LensSystemDraw& remade);

}  // namespace octarc
