// Training the learned selection (METHOD.md section 4, SELECTION_METHOD TREES): gradient-boosted
// trees that tell the simulated arcs of a lens population from a survey's own objects, the
// paper's premise being that nearly every survey object is not a lens.
//
//   simulated arcs (every arc row, every level, of the ARC_FOUND = 1 systems, with the context
//   columns simulate lenses writes; each system weighs its SIM_WEIGHT, shared among its rows)
//   + the survey catalog's rows (every level; context computed here)
//   --> rows above the S/N floor and resolved, as the search takes them
//   --> the two classes weighted to equal sums --> selection/TreeModel.h --> the model file
#pragma once

#include "octarc/calibration/SimulationOutput.h"
#include "octarc/core/Table.h"
#include "octarc/selection/LensModel.h"

namespace octarc {

struct LensModelSettings {
  double snrMin = 40.0;            // the search's SNR_MIN
  double resolvedMinArcsec = 1.0;  // the search's RESOLVED_MIN
  double contextRadiusArcsec = 6.0;
  TreeTraining trees;
};

// The model of the simulation's setup. ConfigError when either class has no row, or a column is
// missing (a simulation older than the context columns is named as such).
SavedLensModel trainLensModel(const SimulationOutput& simulation, const Table& survey,
                              const LensModelSettings& settings);

}  // namespace octarc
