#include "search.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Table.h"
#include "octarc/io/FitsTable.h"
#include "octarc/run/ImageRun.h"
#include "octarc/search/InjectionDemo.h"
#include "octarc/search/InjectionMatch.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/search/SearchRun.h"
#include "run_inputs.h"
#include "selection.h"
#include "tables.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// What octarc.search returns to the Python package. The run keeps its catalog and candidates
// (for match_injections); its image, footprints and lens-light images are freed once the
// candidates are made.
struct SearchOutput {
  SearchRun run;
  FitsTable candidates;  // as OUTPUT_DIR/candidates.fits holds them
  RunValues values;
  std::vector<std::string> summary;   // searchSummaryLines
  std::vector<double> thresholdsAdu;  // per level, lowest first
};

// `selector`: a _Grid, a _Model or None (the configuration's GRID_NAME or MODEL_NAME file).
std::unique_ptr<SearchOutput> search(const py::array& data, const py::object& background,
                                     const py::object& error, const py::object& weight,
                                     const py::object& mask, const py::object& kernel,
                                     const std::vector<std::string>& headerCards, Keys keys,
                                     const std::string& configFile, const py::object& selector) {
  std::optional<SavedGrid> grid;
  std::optional<SavedLensModel> model;
  std::string selectorPath;  // set after the configuration: a path is no configuration value
  if (py::isinstance<GridHandle>(selector)) {
    const GridHandle& g = selector.cast<const GridHandle&>();
    keys.emplace_back("SELECTION_METHOD", "GRID");
    selectorPath = g.path;
    grid = g.saved;
  } else if (py::isinstance<ModelHandle>(selector)) {
    const ModelHandle& h = selector.cast<const ModelHandle&>();
    keys.emplace_back("SELECTION_METHOD", "TREES");
    selectorPath = h.path;
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
  SearchRunSettings settings = searchSettingsFromConfig(inputs.config(), std::move(runSettings));
  if (grid) settings.gridPath = selectorPath;
  if (model) settings.modelPath = selectorPath;
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
    out->values = runValues(image, inputs);
    out->run = runGuarded([&] {
      return searchPreparedImage(settings, std::move(image), std::move(grid), std::move(model),
                                 [&signals] { signals(); }, {});
    });
    SearchRun& run = out->run;
    out->candidates = searchCandidateTable(run, settings);
    out->summary = searchSummaryLines(run, settings);
    for (const ThresholdLevel& l : run.levels) out->thresholdsAdu.push_back(l.thresholdAdu);
    run.image = PreparedImage();
    run.footprints.reset();
    run.lensLight.reset();
    run.colourImages.clear();
    run.grid.reset();
    run.model.reset();
  }
  return out;
}

// The truth list of a simulated field (octarc.simulate_field's truth table, or its .truth.txt
// file read back) as the matching reads it.
std::vector<TruthRow> truthRows(const py::dict& columns) {
  const Table table = tableOf(columns, "truth");
  const char* names[] = {"ID",   "X_IMAGE", "Y_IMAGE", "ALPHA_J2000", "DELTA_J2000",
                         "KIND", "MAG",     "THETA_E", "SYSTEM"};
  int c[9];
  for (int k = 0; k < 9; ++k) c[k] = table.requireColumn(names[k], "truth");
  // ID, KIND and SYSTEM are whole numbers: checked before they are converted.
  auto whole = [&](std::int64_t r, int k) {
    const double v = table.value(r, c[k]);
    if (!(std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)) {
      throw py::value_error("truth: " + std::string(names[k]) + " in row " + std::to_string(r + 1) +
                            " is not a whole number");
    }
    return std::int64_t(v);
  };
  std::vector<TruthRow> rows(std::size_t(table.rows()));
  for (std::int64_t r = 0; r < table.rows(); ++r) {
    TruthRow& t = rows[std::size_t(r)];
    t.id = whole(r, 0);
    t.xFits = table.value(r, c[1]);
    t.yFits = table.value(r, c[2]);
    t.raDeg = table.value(r, c[3]);
    t.decDeg = table.value(r, c[4]);
    const std::int64_t kind = whole(r, 5);
    if (kind < 1 || kind > 4) {
      throw py::value_error("truth: KIND " + std::to_string(kind) + " in row " +
                            std::to_string(r + 1) + " is not 1 to 4");
    }
    t.kind = simulation::FieldObjectKind(kind);
    t.mag = table.value(r, c[6]);
    t.einsteinRadiusArcsec = table.value(r, c[7]);
    const std::int64_t system = whole(r, 8);
    if (system < 0 || system > std::numeric_limits<int>::max()) {
      throw py::value_error("truth: SYSTEM in row " + std::to_string(r + 1) + " is out of range");
    }
    t.systemId = int(system);
  }
  return rows;
}

// Which injected lenses the search found (search/InjectionMatch.h, as octarc demo matches
// them): per system its truth, candidate (0-based, -1 none), the candidate's report spaces,
// whether it names the right lens and its THETA_E; per candidate the system it is an arc of.
py::dict matchInjections(const SearchOutput& out, const py::dict& truth, double matchArcsec,
                         double lensMatchArcsec) {
  const std::vector<TruthRow> rows = truthRows(truth);
  InjectionMatch match;
  {
    py::gil_scoped_release release;
    match = matchInjectedLenses(rows, out.run.catalog, out.run.result, out.run.pixelScaleArcsec,
                                ArcRules(), matchArcsec, lensMatchArcsec);
  }
  const std::size_t n = match.systems.size();
  py::array_t<std::int32_t> system(n), spaces(n);
  py::array_t<double> thetaE(n), arcMag(n), estimate(n);
  py::array_t<std::int64_t> candidate(n);
  py::array_t<bool> lensRight(n);
  for (std::size_t k = 0; k < n; ++k) {
    const InjectedLensOutcome& o = match.systems[k];
    system.mutable_at(k) = o.system;
    thetaE.mutable_at(k) = o.einsteinRadiusArcsec;
    arcMag.mutable_at(k) = o.arcMag;
    candidate.mutable_at(k) = o.candidate;
    spaces.mutable_at(k) = std::int32_t(o.spaces);
    lensRight.mutable_at(k) = o.lensRight;
    estimate.mutable_at(k) = o.einsteinRadiusEstimateArcsec;
  }
  py::dict systems;
  systems["SYSTEM"] = system;
  systems["THETA_E"] = thetaE;
  systems["ARC_MAG"] = arcMag;
  systems["CANDIDATE"] = candidate;
  systems["SPACES"] = spaces;
  systems["LENS_RIGHT"] = lensRight;
  systems["THETA_E_ESTIMATE"] = estimate;
  py::dict result;
  result["systems"] = systems;
  result["candidate_system"] = match.candidateSystem;
  return result;
}

}  // namespace

void bindSearch(py::module_& m) {
  py::class_<SearchOutput>(m, "_Search",
                           "What octarc.search found: the candidates and every row searched "
                           "(octarc.SearchResult wraps it).")
      .def_readonly("candidates", &SearchOutput::candidates,
                    "The candidates, as OUTPUT_DIR/candidates.fits holds them.")
      .def(
          "catalog",
          [](const SearchOutput& o) {
            // In catalog order, made when asked (an empty order: the rows as stored).
            return o.run.catalogOrder.empty() ? o.run.catalog
                                              : rowsInOrder(o.run.catalog, o.run.catalogOrder);
          },
          "Every row searched, in catalog order (a new table at each call).")
      .def_property_readonly(
          "values", [](const SearchOutput& o) { return o.values.asDict(); },
          "The run's background and noise (ADU) and where they came from.")
      .def_readonly("thresholds", &SearchOutput::thresholdsAdu,
                    "The detection threshold of each level, ADU, lowest first.")
      .def_readonly("summary", &SearchOutput::summary, "The summary lines octarc search prints.")
      .def_property_readonly(
          "warnings", [](const SearchOutput& o) { return o.run.warnings; },
          "The search's warnings (a grid made for another setup, no WCS, ...).")
      .def_property_readonly(
          "pixel_scale", [](const SearchOutput& o) { return o.run.pixelScaleArcsec; },
          "The pixel scale searched with, arcsec.")
      .def("match_injections", &matchInjections, py::arg("truth"), py::arg("match_radius"),
           py::arg("lens_match_radius"),
           "Which injected lenses of a truth list the candidates are arcs of.");
  m.attr("_DEMO_ARC_MATCH_ARCSEC") = kDemoArcMatchArcsec;
  m.attr("_DEMO_LENS_MATCH_ARCSEC") = kDemoLensMatchArcsec;
  m.def("_search", &search, py::arg("data"), py::arg("background"), py::arg("error"),
        py::arg("weight"), py::arg("mask"), py::arg("kernel"), py::arg("header_cards"),
        py::arg("keys"), py::arg("config_file"), py::arg("selector"),
        "The search of an image in memory (octarc.search calls it).");
}

}  // namespace octarc::python
