#include "measurement.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "arrays.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Table.h"
#include "octarc/detection/SegmentationReader.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/MeasurementRun.h"
#include "run_inputs.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// What octarc.measure returns to the Python package.
struct MeasurementOutput {
  Table table;  // every built-in column, one row per object: level by level, label order
  std::vector<ThresholdLevel> levels;
  RunValues values;
};

std::unique_ptr<MeasurementOutput> measure(const py::array& data, const py::list& segmentation,
                                           const py::object& thresholds, bool relative,
                                           const py::object& background, const py::object& error,
                                           const py::object& weight, const py::object& mask,
                                           const py::object& kernel,
                                           const std::vector<std::string>& headerCards,
                                           const Keys& keys) {
  Keys all = keys;
  all.emplace_back("THRESH_TYPE", relative ? "RELATIVE" : "ABSOLUTE");
  const std::size_t levelCount = segmentation.size();
  if (levelCount == 0) throw py::value_error("segmentation: at least one label image is needed");
  if (!thresholds.is_none()) {
    const std::vector<double> values = thresholds.cast<std::vector<double>>();
    if (values.size() != levelCount) {
      throw py::value_error("thresholds: " + std::to_string(values.size()) + " threshold(s) for " +
                            std::to_string(levelCount) + " segmentation level(s)");
    }
    if (levelCount == 1) {
      all.emplace_back("DETECT_THRESH", numberText(values[0]));
      all.emplace_back("ANALYSIS_THRESH", numberText(values[0]));
    } else {
      std::string list;
      for (double t : values) list += (list.empty() ? "" : ",") + numberText(t);
      all.emplace_back("DETECT_LEVELS", list);
    }
  } else if (levelCount > 1) {
    throw py::value_error("thresholds: several segmentation levels need their thresholds");
  }
  RunInputs inputs(data, background, error, weight, mask, kernel, headerCards, all);
  // The label images, int32 C-contiguous (the Python package converts others once).
  std::vector<py::array_t<std::int32_t>> labelArrays;
  for (std::size_t k = 0; k < levelCount; ++k) {
    const std::string what = "segmentation[" + std::to_string(k) + "]";
    py::array array = py::array::ensure(segmentation[k]);
    if (!array || !py::isinstance<py::array_t<std::int32_t, py::array::c_style>>(array)) {
      throw py::value_error(what + ": an int32 C-contiguous array is needed");
    }
    if (array.ndim() != 2 || array.shape(0) != inputs.data().height ||
        array.shape(1) != inputs.data().width) {
      throw py::value_error(what + ": not a 2-D array of the shape of data");
    }
    labelArrays.push_back(py::array_t<std::int32_t>(array));
  }
  std::vector<const std::int32_t*> labelData;
  for (const auto& a : labelArrays) labelData.push_back(a.data());

  const MeasurementPlan plan = allColumnsPlan();
  auto out = std::make_unique<MeasurementOutput>();
  {
    py::gil_scoped_release release;
    SignalCheck signals;
    const PreparedImage image = inputs.prepare(false, signals);
    const RunSettings& settings = inputs.settings();
    std::vector<ImageI32> levels;
    std::vector<std::string> names;
    for (std::size_t k = 0; k < levelCount; ++k) {
      ImageI32 labels(inputs.data().width, inputs.data().height, UninitializedPixels{});
      std::copy(labelData[k], labelData[k] + labels.size(), labels.data());
      levels.push_back(std::move(labels));
      names.push_back("segmentation[" + std::to_string(k) + "]");
    }
    const std::vector<Segment> segments =
        runGuarded([&] { return segmentsFromLabels(levels, names); });
    std::vector<ImageI32>().swap(levels);
    signals();
    MeasureContext context = image.context(settings);
    out->levels =
        runGuarded([&] { return levelThresholds(settings, image.sigmaAdu, {}, levelCount); });
    context.levels = out->levels;
    out->table = Table(plan.columns());
    measureSegments(plan, segments, context, out->table, resolveThreads(settings.threads));
    out->values = runValues(image, inputs);
  }
  return out;
}

}  // namespace

void bindMeasurement(py::module_& m) {
  py::class_<MeasurementOutput>(m, "_Measurement",
                                "What octarc.measure measured: the catalog table and the levels "
                                "(octarc.MeasurementResult wraps it).")
      .def_property_readonly(
          "table", [](const MeasurementOutput& o) -> const Table& { return o.table; },
          py::return_value_policy::reference_internal, "Every row: level by level, in label order.")
      .def_property_readonly(
          "thresholds",
          [](const MeasurementOutput& o) {
            std::vector<double> t;
            for (const ThresholdLevel& l : o.levels) t.push_back(l.thresholdAdu);
            return t;
          },
          "The threshold of each level, ADU, lowest first.")
      .def_property_readonly(
          "values", [](const MeasurementOutput& o) { return o.values.asDict(); },
          "The run's background and noise (ADU) and where they came from.");
  m.def("_measure", &measure, py::arg("data"), py::arg("segmentation"), py::arg("thresholds"),
        py::arg("relative"), py::arg("background"), py::arg("error"), py::arg("weight"),
        py::arg("mask"), py::arg("kernel"), py::arg("header_cards"), py::arg("keys"),
        "Measurement of the objects of label images (octarc.measure calls it).");
}

}  // namespace octarc::python
