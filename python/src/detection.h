// octarc.detect: multi-threshold detection and measurement of an image held in numpy arrays,
// through the library calls `octarc detect` makes (run/PreparedImage.h, run/ImageRun.h).
#pragma once

#include <pybind11/pybind11.h>

namespace octarc::python {

void bindDetection(pybind11::module_& m);

}  // namespace octarc::python
