// octarc's catalog tables (core/Table.h) seen from Python: the declared columns (name, unit,
// description, UCD, storage type) and each column as a numpy array of its storage type.
#pragma once

#include <pybind11/pybind11.h>

namespace octarc::python {

void bindTables(pybind11::module_& m);

}  // namespace octarc::python
