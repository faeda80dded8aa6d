// The search stage for Python: octarc.search on an image in memory.
#pragma once

#include <pybind11/pybind11.h>

namespace octarc::python {

void bindSearch(pybind11::module_& m);

}  // namespace octarc::python
