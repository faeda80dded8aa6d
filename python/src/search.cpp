#include "search.h"

#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Table.h"
#include "octarc/io/FitsTable.h"
#include "octarc/run/ImageRun.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/search/SearchRun.h"
#include "run_inputs.h"
#include "selection.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// What octarc.search returns to the Python package.
struct SearchOutput {
  SearchRunSettings settings;
  SearchRun run;
  FitsTable candidates;  // as OUTPUT_DIR/candidates.fits holds them
  Table catalog;         // every row searched, in catalog order
  RunValues values;
};

// `selector`: a _Grid, a _Model or None (the configuration's GRID_NAME or MODEL_NAME file).
std::unique_ptr<SearchOutput> search(const py::array& data, const py::object& background,
                                     const py::object& error, const py::object& weight,
                                     const py::object& mask, const py::object& kernel,
                                     const std::vector<std::string>& headerCards, Keys keys,
                                     const std::string& configFile, const py::object& selector) {
  std::optional<SavedGrid> grid;
  std::optional<SavedLensModel> model;
  if (py::isinstance<GridHandle>(selector)) {
    const GridHandle& g = selector.cast<const GridHandle&>();
    keys.emplace_back("SELECTION_METHOD", "GRID");
    keys.emplace_back("GRID_NAME", g.path);
    grid = g.saved;
  } else if (py::isinstance<ModelHandle>(selector)) {
    const ModelHandle& h = selector.cast<const ModelHandle&>();
    keys.emplace_back("SELECTION_METHOD", "TREES");
    keys.emplace_back("MODEL_NAME", h.path);
    model = copyOf(h.saved);
  }
  // The stamps and the vetting page are written by the command; here nothing is.
  keys.emplace_back("STAMPS", "N");
  RunInputs inputs(data, background, error, weight, mask, kernel, headerCards, keys,
                   {searchKeys(), configFile, true});
  RunSettings runSettings = inputs.settings();
  // Not given: the shipped column list (octarc search's default without a ./default.param).
  runSettings.parametersPath =
      inputs.config().isExplicit("PARAMETERS_NAME")
          ? existingUserOrDataFile(runSettings.parametersPath, "PARAMETERS_NAME file")
          : dataFile("octarc.param");
  auto out = std::make_unique<SearchOutput>();
  out->settings = searchSettingsFromConfig(inputs.config(), std::move(runSettings));
  const SearchRunSettings& settings = out->settings;
  if (settings.search.method == SelectionMethod::Trees && !model) {
    model = loadLensModel(existingUserOrDataFile(settings.modelPath, "MODEL_NAME file"));
  } else if (settings.search.method == SelectionMethod::Grid && !grid) {
    grid = loadGrid(existingUserOrDataFile(settings.gridPath, "GRID_NAME file"));
  }
  {
    py::gil_scoped_release release;
    SignalCheck signals;
    const bool relative = settings.run.detectThresholdType == ThresholdType::Relative;
    PreparedImage image = inputs.prepare(relative, signals);
    out->values = runValues(image);
    out->run = runGuarded([&] {
      return searchPreparedImage(settings, std::move(image), std::move(grid), std::move(model),
                                 [&signals] { signals(); }, {});
    });
    out->candidates = searchCandidateTable(out->run, settings);
    out->catalog = rowsInOrder(out->run.catalog, out->run.catalogOrder);
  }
  return out;
}

}  // namespace

void bindSearch(py::module_& m) {
  py::class_<SearchOutput>(m, "_Search",
                           "What octarc.search found: the candidates and every row searched "
                           "(octarc.SearchResult wraps it).")
      .def_readonly("candidates", &SearchOutput::candidates,
                    "The candidates, as OUTPUT_DIR/candidates.fits holds them.")
      .def_readonly("catalog", &SearchOutput::catalog, "Every row searched, in catalog order.")
      .def_property_readonly(
          "values", [](const SearchOutput& o) { return o.values.asDict(); },
          "The run's background and noise (ADU) and where they came from.")
      .def_property_readonly(
          "thresholds",
          [](const SearchOutput& o) {
            std::vector<double> t;
            for (const ThresholdLevel& l : o.run.levels) t.push_back(l.thresholdAdu);
            return t;
          },
          "The detection threshold of each level, ADU, lowest first.")
      .def_property_readonly(
          "summary", [](const SearchOutput& o) { return searchSummaryLines(o.run, o.settings); },
          "The summary lines octarc search prints.")
      .def_property_readonly(
          "warnings", [](const SearchOutput& o) { return o.run.warnings; },
          "The search's warnings (a grid made for another setup, no WCS, ...).")
      .def_property_readonly(
          "pixel_scale", [](const SearchOutput& o) { return o.run.pixelScaleArcsec; },
          "The pixel scale searched with, arcsec.");
  m.def("_search", &search, py::arg("data"), py::arg("background"), py::arg("error"),
        py::arg("weight"), py::arg("mask"), py::arg("kernel"), py::arg("header_cards"),
        py::arg("keys"), py::arg("config_file"), py::arg("selector"),
        "The search of an image in memory (octarc.search calls it).");
}

}  // namespace octarc::python
