#include "detection.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Table.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/measure/Registry.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunKeys.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/ConvFile.h"
#include "run_inputs.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// What octarc.detect returns to the Python package.
struct DetectionOutput {
  Table table;  // every built-in column, rows in catalog order (level by level, NUMBER order)
  std::vector<ThresholdLevel> levels;
  std::vector<std::int64_t> objectsPerLevel;
  std::optional<SegmentationRuns> segmentation;
  RunValues values;
};

std::unique_ptr<DetectionOutput> detect(
    const py::array& data, const std::vector<double>& thresholds, bool relative, int minarea,
    const py::object& background, const py::object& error, const py::object& weight,
    const py::object& mask, const py::object& kernel, const std::vector<std::string>& headerCards,
    const std::vector<std::pair<std::string, std::string>>& keys, bool keepSegmentation) {
  if (thresholds.empty()) throw py::value_error("thresholds: at least one threshold is needed");
  std::vector<std::pair<std::string, std::string>> all = keys;
  all.emplace_back("THRESH_TYPE", relative ? "RELATIVE" : "ABSOLUTE");
  if (thresholds.size() == 1) {
    // One level is a plain SExtractor run; its isophote is the detection threshold.
    all.emplace_back("DETECT_THRESH", numberText(thresholds[0]));
    all.emplace_back("ANALYSIS_THRESH", numberText(thresholds[0]));
  } else {
    std::string list;
    for (double t : thresholds) list += (list.empty() ? "" : ",") + numberText(t);
    all.emplace_back("DETECT_LEVELS", list);
  }
  all.emplace_back("DETECT_MINAREA", std::to_string(minarea));
  RunInputs inputs(data, background, error, weight, mask, kernel, headerCards, all);
  const MeasurementPlan plan = allColumnsPlan();

  auto out = std::make_unique<DetectionOutput>();
  {
    py::gil_scoped_release release;
    SignalCheck signals;
    PreparedImage image = inputs.prepare(relative, signals);
    const RunSettings& settings = inputs.settings();
    out->levels = detectionLevels(settings, image.detectionSigma());
    MeasureContext context = image.context(settings);
    context.levels = out->levels;
    DetectionRequest request = configuredRequest(settings, out->levels);
    request.keepSegmentation = keepSegmentation;
    request.checkpoint = [&signals] { signals(); };
    ImageRunResult run =
        runGuarded([&] { return detectAndMeasure(image, plan, context, request, &settings); });
    out->objectsPerLevel = run.objectsPerLevel;
    out->table = rowsInOrder(run.rows, run.catalogOrder);
    out->segmentation = std::move(run.segmentation);
    out->values = runValues(image, inputs);
  }
  return out;
}

// Level `level` (1 = lowest) of the segmentation as a numpy int32 array that owns the labels
// octarc rendered (no copy).
py::array segmentationImage(const DetectionOutput& out, int level) {
  if (!out.segmentation) {
    throw py::value_error("segmentation: the run was made with segmentation=False");
  }
  const int count = out.segmentation->levelCount();
  if (level < 1 || level > count) {
    throw py::value_error("segmentation: level " + std::to_string(level) + " is not in 1.." +
                          std::to_string(count));
  }
  auto labels = std::make_unique<ImageI32>();
  {
    py::gil_scoped_release release;
    out.segmentation->render(level, *labels);
  }
  return ownedArray(std::move(labels));
}

}  // namespace

void bindDetection(py::module_& m) {
  py::class_<DetectionOutput>(m, "_Detection",
                              "What octarc.detect found: the catalog table, the levels and the "
                              "segmentation (octarc.DetectionResult wraps it).")
      .def_property_readonly(
          "table", [](const DetectionOutput& o) -> const Table& { return o.table; },
          py::return_value_policy::reference_internal, "Every row, in catalog order.")
      .def_property_readonly(
          "thresholds",
          [](const DetectionOutput& o) {
            std::vector<double> t;
            for (const ThresholdLevel& l : o.levels) t.push_back(l.thresholdAdu);
            return t;
          },
          "The detection threshold of each level, ADU, lowest first.")
      .def_readonly("objects_per_level", &DetectionOutput::objectsPerLevel,
                    "The number of objects at each level, lowest first.")
      .def_property_readonly(
          "values", [](const DetectionOutput& o) { return o.values.asDict(); },
          "The run's background and noise (ADU) and where they came from.")
      .def("segmentation", &segmentationImage, py::arg("level"),
           "The labels (NUMBER, 0 = no object) of level `level` (1 = lowest) as an int32 "
           "array.");
  m.def("_detect", &detect, py::arg("data"), py::arg("thresholds"), py::arg("relative"),
        py::arg("minarea"), py::arg("background"), py::arg("error"), py::arg("weight"),
        py::arg("mask"), py::arg("kernel"), py::arg("header_cards"), py::arg("keys"),
        py::arg("keep_segmentation"),
        "Detection and measurement of an image in memory (octarc.detect calls it).");
}

}  // namespace octarc::python
