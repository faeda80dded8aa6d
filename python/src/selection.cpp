#include "selection.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "octarc/core/DataFiles.h"
#include "octarc/core/Parallel.h"
#include "octarc/selection/ArcContext.h"
#include "octarc/selection/GridScore.h"
#include "tables.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// The survey setup a grid or a model was made for, as a dict (NaN where not recorded).
py::dict setupDict(const SurveySetup& setup) {
  py::dict out;
  out["pixel_scale"] = setup.pixelScaleArcsec;
  out["seeing_fwhm"] = setup.seeingFwhmArcsec;
  out["gain"] = setup.gainElectronsPerAdu;
  out["sky_sigma"] = setup.skySigmaAdu;
  out["thresholds"] = setup.thresholdsSigma;
  out["minarea"] = setup.minAreaPix;
  out["population_file"] = setup.populationFile;
  out["seed"] = setup.seed;
  out["systems"] = setup.systems;
  return out;
}

// Every row's grid score: PROBABILITY (of its bin, 0 outside the occupied bins), CONTOUR_LEVEL
// (the level at which its bin enters the contour, NaN outside the occupied bins), SELECTED (in
// the contour) and GRID_STATUS (0 occupied bin, 1 empty bin, 2 outside the axes, 3 undefined).
py::dict scoreWithGrid(const GridHandle& grid, const py::dict& columns) {
  const Table table = tableOf(columns, "Grid.score");
  std::vector<RowScore> scores;
  {
    py::gil_scoped_release release;
    scores = scoreRows(grid.saved.grid, grid.saved.contour, table);
  }
  const std::size_t rows = scores.size();
  py::array_t<double> probability(rows), level(rows);
  py::array_t<bool> selected(rows);
  py::array_t<std::int16_t> status(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    probability.mutable_at(r) = scores[r].probability;
    level.mutable_at(r) = scores[r].entryLevel;
    selected.mutable_at(r) = scores[r].selected;
    status.mutable_at(r) = std::int16_t(scores[r].status);
  }
  py::dict out;
  out["PROBABILITY"] = probability;
  out["CONTOUR_LEVEL"] = level;
  out["SELECTED"] = selected;
  out["GRID_STATUS"] = status;
  return out;
}

// Every row's log-odds of being a lens arc for the model's training mix. The context features
// are the table's columns when it holds them all (simulated arcs do), else computed from its
// rows (a survey catalog: every row of one image, selection/ArcContext.h).
py::array_t<double> modelLogOdds(const ModelHandle& model, const py::dict& columns,
                                 double pixelScaleArcsec, int threads) {
  const Table table = tableOf(columns, "Model.score");
  if (!(pixelScaleArcsec > 0)) {
    throw py::value_error(
        "Model.score: pixel_scale (arcsec) must be > 0; give it when the model's setup records "
        "none");
  }
  bool hasContext = true;
  for (const ColumnSpec& c : arcContextColumns()) hasContext &= table.findColumn(c.name) >= 0;
  std::vector<double> logOdds;
  {
    py::gil_scoped_release release;
    std::vector<std::int64_t> rows(std::size_t(table.rows()));
    std::iota(rows.begin(), rows.end(), std::int64_t{0});
    std::vector<ArcContext> contexts;
    if (!hasContext) {
      contexts = arcContexts(table, {pixelScaleArcsec, model.saved.contextRadiusArcsec});
    }
    const FeatureRows features =
        lensFeatures(table, rows, pixelScaleArcsec, hasContext ? nullptr : &contexts);
    logOdds = model.saved.trees.logOdds(features, resolveThreads(threads));
  }
  py::array_t<double> out(logOdds.size());
  std::copy(logOdds.begin(), logOdds.end(), out.mutable_data());
  return out;
}

}  // namespace

SavedLensModel copyOf(const SavedLensModel& model) {
  SavedLensModel copy;
  copy.trees = TreeModel::fromJson(model.trees.toJson(), model.trees.features());
  copy.features = model.features;
  copy.contextRadiusArcsec = model.contextRadiusArcsec;
  copy.training = model.training;
  copy.setup = model.setup;
  return copy;
}

void bindSelection(py::module_& m) {
  py::class_<GridHandle>(m, "_Grid", "An occupation grid as read from its file.")
      .def_readonly("path", &GridHandle::path)
      .def_property_readonly(
          "axes",
          [](const GridHandle& g) {
            py::list out;
            for (const GridAxis& a : g.saved.grid.binning().axes()) {
              out.append(py::make_tuple(a.expression, a.lo, a.hi, a.bins));
            }
            return out;
          },
          "The axes: (expression, lo, hi, bins) each.")
      .def_property_readonly(
          "level", [](const GridHandle& g) { return g.saved.contour.level; },
          "The contour level P the grid selects at.")
      .def_property_readonly(
          "selected_bins", [](const GridHandle& g) { return g.saved.contour.selectedBins; },
          "The number of bins in the contour.")
      .def_property_readonly(
          "search_space",
          [](const GridHandle& g) {
            return py::make_tuple(g.saved.provenance.searchSpace,
                                  g.saved.provenance.searchSpaceExpression);
          },
          "The search space the grid was made in: (name, cut), empty for every arc.")
      .def_property_readonly(
          "setup", [](const GridHandle& g) { return setupDict(g.saved.provenance.setup); },
          "The survey setup the grid was made for.")
      .def("score", &scoreWithGrid, py::arg("columns"),
           "The grid's score of every row of `columns` (a dict of 1-D arrays by name).");
  py::class_<ModelHandle>(m, "_Model", "A lens model as read from its file.")
      .def_readonly("path", &ModelHandle::path)
      .def_property_readonly(
          "features", [](const ModelHandle& h) { return h.saved.features; },
          "The features of a row, in the model's order.")
      .def_property_readonly(
          "context_radius", [](const ModelHandle& h) { return h.saved.contextRadiusArcsec; },
          "How far the context features look, arcsec.")
      .def_property_readonly(
          "setup", [](const ModelHandle& h) { return setupDict(h.saved.setup); },
          "The survey setup the model was trained for.")
      .def(
          "lens_scores",
          [](const ModelHandle& h, const py::array_t<double>& logOdds, double priorFraction) {
            if (!(priorFraction > 0 && priorFraction < 1)) {
              throw py::value_error("Model.score: prior must lie in (0, 1), not " +
                                    std::to_string(priorFraction));
            }
            // As the search scores its rows (search/Search.h).
            const double shift = priorLogOddsShift(h.saved.training, priorFraction);
            py::array_t<double> out(logOdds.size());
            for (py::ssize_t r = 0; r < logOdds.size(); ++r) {
              out.mutable_at(r) = logistic(logOdds.at(r) + shift);
            }
            return out;
          },
          py::arg("log_odds"), py::arg("prior"),
          "LENS_SCORE from the log-odds, for rows holding lens arcs at the fraction `prior`.")
      .def("log_odds", &modelLogOdds, py::arg("columns"), py::arg("pixel_scale"),
           py::arg("threads"), "The trees' log-odds of every row of `columns`.");
  m.def(
      "_read_grid",
      [](const std::string& path) {
        const std::string file = existingUserOrDataFile(path, "grid file");
        return GridHandle{loadGrid(file), file};
      },
      py::arg("path"), "Reads a grid file (a shipped one by its name, e.g. demo.grid.fits).");
  m.def(
      "_read_model",
      [](const std::string& path) {
        const std::string file = existingUserOrDataFile(path, "lens model file");
        return ModelHandle{loadLensModel(file), file};
      },
      py::arg("path"), "Reads a lens model file (a shipped one by its name).");
}

}  // namespace octarc::python
