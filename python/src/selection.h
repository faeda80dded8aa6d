// The selection stage for Python: octarc.Grid and octarc.Model, the occupation grid and the lens
// model read from their files, scoring the rows of a table.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "octarc/selection/GridFile.h"
#include "octarc/selection/LensModel.h"

namespace octarc::python {

// A grid or a lens model as read, with the path it was read from (octarc.search takes them).
struct GridHandle {
  SavedGrid saved;
  std::string path;
};
struct ModelHandle {
  SavedLensModel saved;
  std::string path;
};

// A copy of a model (the trees through their JSON, XGBoost's boosters not being copyable), for a
// search that keeps its own while the Python object stays usable.
SavedLensModel copyOf(const SavedLensModel& model);

void bindSelection(pybind11::module_& m);

}  // namespace octarc::python
