// octarc.measure: octarc's measurements of the objects of given segmentation images (one per
// threshold level, as SExtractor writes them), through the library calls `octarc measure` makes
// (run/PreparedImage.h, detection/SegmentationReader.h, run/CatalogAssembly.h).
#pragma once

#include <pybind11/pybind11.h>

namespace octarc::python {

void bindMeasurement(pybind11::module_& m);

}  // namespace octarc::python
