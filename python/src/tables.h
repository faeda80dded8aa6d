// octarc's catalog tables (core/Table.h) seen from Python: the declared columns (name, unit,
// description, UCD, storage type) and each column as a numpy array of its storage type; FITS
// tables made in memory (io/FitsTable.h, e.g. the search's candidates) likewise; and a table of
// the caller's columns made into an octarc Table.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "octarc/core/Table.h"

namespace octarc::python {

void bindTables(pybind11::module_& m);

// An octarc Table of float64 columns from a dict of 1-D numeric arrays of one length (an
// astropy Table's columns, by name); ValueError naming `what` and the column otherwise.
Table tableOf(const pybind11::dict& columns, const std::string& what);

}  // namespace octarc::python
