// octarc's simulations seen from Python: `octarc simulate lenses` (the systems and arc tables,
// the stamps, in memory) and `octarc simulate field` (the image, the weight map, the header and
// the truth list), over the simulation engine's library calls.
#pragma once

#include <pybind11/pybind11.h>

namespace octarc::python {

void bindSimulation(pybind11::module_& m);

}  // namespace octarc::python
