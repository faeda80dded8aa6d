// The octarc Python module's compiled part, octarc._octarc: one binding file per stage
// (tables.cpp, detection.cpp, measurement.cpp, simulation.cpp, selection.cpp, search.cpp),
// over the libraries. The octarc package (python/octarc/__init__.py) wraps it into its public
// API with astropy tables.
#include <pybind11/pybind11.h>

#include <exception>

#include "arrays.h"
#include "detection.h"
#include "measurement.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Version.h"
#include "search.h"
#include "selection.h"
#include "simulation.h"
#include "tables.h"

namespace py = pybind11;

PYBIND11_MODULE(_octarc, m) {
  m.doc() = "octarc's libraries for Python (use the octarc package, not this module).";
  m.attr("__version__") = octarc::kVersion;
  // octarc's one-line errors: a wrong option or value is ValueError, a file OSError.
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const octarc::python::PythonSignal&) {
      // The Python error (KeyboardInterrupt) is already set by PyErr_CheckSignals.
      if (!PyErr_Occurred()) PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const octarc::ConfigError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const octarc::IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const octarc::Error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  m.def("_set_data_directory", &octarc::setDataDirectory, py::arg("directory"),
        "Where the libraries find octarc's shipped files (the package finds it at import).");
  octarc::python::bindTables(m);
  octarc::python::bindDetection(m);
  octarc::python::bindMeasurement(m);
  octarc::python::bindSelection(m);
  octarc::python::bindSearch(m);
  octarc::python::bindSimulation(m);
}
