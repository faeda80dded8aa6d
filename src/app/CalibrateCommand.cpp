// `octarc calibrate`: the studies of simulated lenses (METHOD.md section 3) and the occupation
// grid of their arcs (section 4).
//
//   simulate-lenses output(s) [+ survey catalog] --> calibration/Calibration.h
//   --> CALIBRATION_NAME (tables), GRID_NAME (the grid), CHECKPLOT_NAME (check-plots)

#include <cstdio>
#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/calibration/Calibration.h"
#include "octarc/calibration/CalibrationKeys.h"
#include "octarc/calibration/CalibrationSummary.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Progress.h"
#include "octarc/io/FitsTable.h"
#include "octarc/plot/CheckPlot.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {

namespace {

void printCalibrateUsage() {
  std::cout
      << "Usage: octarc calibrate SIM.fits [SIM2.fits ...] [-c calibrate.conf] [-KEY value ...]\n"
         "\n"
         "Reads the output of octarc simulate lenses (several outputs of the same survey setup\n"
         "are taken together) and writes\n"
         "  CALIBRATION_NAME  the lensing-fraction table (arcness 0.05-0.10, 0.10-0.15, > 0.15,\n"
         "                    each also with E_IMAGE > ELLIP_MIN and SNR_ISO > SNR_MIN, of the\n"
         "                    systems with an arc, weighted by SIM_WEIGHT, with Clopper-Pearson\n"
         "                    68% intervals), the weighted distributions of arcness,\n"
         "                    anti-arcness, skewness, e and S/N (with SURVEY_CATALOG: also of the\n"
         "                    survey's objects), the noise-only threshold (NOISE_STUDY), the\n"
         "                    threshold-count curve (THRESHOLD_STUDY), the S/N floor (SNR_STUDY),\n"
         "                    for a simulation with a second band (simulate lenses --band B)\n"
         "                    the colour cut study (the fraction of arcs COLOUR_CUT B,MAX keeps,\n"
         "                    against MAX: COLOUR_CUT_MAX) and the distribution of\n"
         "                    ARC_COLOUR_B - LENS_COLOUR_B, and the binning search of the grid;\n"
         "  GRID_NAME         the occupation-probability grid of the simulated arcs (in the\n"
         "                    search space SEARCH_CUT), at the finest binning whose contour at\n"
         "                    GRID_LEVEL stays connected (on fewer axes, with a WARNING, when\n"
         "                    none does on them all; none at all with too few arcs; NONE: no\n"
         "                    grid);\n"
         "  MODEL_NAME        with SURVEY_CATALOG: the learned selection (gradient-boosted\n"
         "                    trees telling the simulated arcs from the survey's rows, with the\n"
         "                    context of each: the nearest brighter galaxy, the angle to it, a\n"
         "                    counter-image), for the search's SELECTION_METHOD TREES;\n"
         "  CHECKPLOT_NAME    one check-plot per CHECKPLOT_TYPE on CHECKPLOT_DEV.\n"
         "\n"
         "Options:\n"
         "  -c FILE      configuration file (SExtractor syntax; -dd lists every key)\n"
         "  -KEY value   override a configuration key (e.g. -CHECKPLOT_DEV PDF)\n"
         "  -d, -dd      print the default configuration\n"
         "  -dp          (an error: calibrate writes tables, not a catalog of chosen columns)\n"
         "  -h           this help;  -v  version\n";
}

}  // namespace

int runCalibrate(const std::vector<std::string>& args) {
  std::optional<LoadedConfig> loaded = loadConfig(args, {"calibrate", printCalibrateUsage, {}},
                                                  calibrationKeys(), false, "simulation file name");
  if (!loaded) return 0;
  if (loaded->positional.empty()) {
    throw ConfigError("give the octarc simulate lenses output(s) to calibrate (see -h)");
  }
  const sexcompat::Config& config = loaded->config;
  const std::vector<std::string>& warnings = loaded->warnings;
  std::vector<SimulationOutput> outputs;
  for (const std::string& path : loaded->positional) outputs.push_back(readSimulationOutput(path));
  const SimulationOutput simulation = combineSimulationOutputs(std::move(outputs));
  CalibrationRun run = calibrationRunFromConfig(config, simulation);
  if (run.settings.thresholdCount) {
    run.settings.thresholdCount->progress =
        terminalProgress("Threshold study", "systems", run.quiet);
  }
  if (run.settings.snrFloor) {
    run.settings.snrFloor->progress = terminalProgress("S/N floor", "arc noise levels", run.quiet);
  }
  if (!run.quiet) {
    for (const std::string& w : warnings) std::cerr << "WARNING: " << w << "\n";
  } else {
    setExpressionWarnings({});
  }

  // The outputs, checked before anything is computed; they appear together at the end.
  std::vector<std::string> paths = {run.calibrationPath};
  if (!run.gridPath.empty()) paths.push_back(run.gridPath);
  if (!run.modelPath.empty()) paths.push_back(run.modelPath);
  for (const CheckPlotRequest& p : run.plots) paths.push_back(p.path);
  std::vector<std::string> inputs = loaded->positional;
  if (!run.surveyCatalogPath.empty()) inputs.push_back(run.surveyCatalogPath);
  {
    OutputFiles check;
    for (const std::string& path : paths) {
      check.add(path);
      for (const std::string& in : inputs) refuseOutputOverInput(path, "output", in, "input");
    }
  }

  std::optional<Table> survey;
  if (!run.surveyCatalogPath.empty()) {
    survey = tableFromFits(readFitsTable(run.surveyCatalogPath, "LDAC_OBJECTS"));
  }
  if (!run.quiet) {
    std::cerr << "> Calibrating " << simulation.setup.systems << " systems ("
              << simulation.systems.rows() << " rendered)\n";
  }
  const CalibrationResult result = calibrate(simulation, survey ? &*survey : nullptr, run.settings);
  std::optional<SavedLensModel> model;
  if (run.model) {
    if (!run.quiet) std::cerr << "> Training the lens model\n";
    model = trainLensModel(simulation, *survey, *run.model);
  }

  // The grid only when one was made: without, the warning below says why.
  OutputFiles files;
  files.add(run.calibrationPath);
  std::optional<std::size_t> gridFile;
  if (!run.gridPath.empty() && result.grid.grid) {
    gridFile = files.size();
    files.add(run.gridPath);
  }
  std::optional<std::size_t> modelFile;
  if (model) {
    modelFile = files.size();
    files.add(run.modelPath);
  }
  const std::size_t firstPlot = files.size();
  for (const CheckPlotRequest& p : run.plots) files.add(p.path);
  files.write(0,
              [&](const std::string& path) { writeFitsTables(path, calibrationTables(result)); });
  if (gridFile) {
    files.write(*gridFile, [&](const std::string& path) { saveGrid(path, *result.grid.grid); });
  }
  if (modelFile) {
    files.write(*modelFile, [&](const std::string& path) { saveLensModel(path, *model); });
  }
  for (std::size_t i = 0; i < run.plots.size(); ++i) {
    Plot plot = calibrationPlot(result, run.plots[i].type);
    plot.widthPix = run.plotWidthPix;
    plot.heightPix = run.plotHeightPix;
    files.write(firstPlot + i,
                [&](const std::string& path) { writePlot(path, run.plotDevice, plot); });
  }
  files.commit();
  if (!run.quiet) printCalibrationSummary(run, result);
  if (model && !run.quiet) {
    const LensModelTraining& t = model->training;
    std::printf(
        "Lens model: %lld trees of depth %d on %s and %lld survey rows (S/N > %g, "
        "resolved > %g\") -> %s\n",
        static_cast<long long>(t.trees.rounds), t.trees.maxDepth,
        countWithEffective(t.arcRows, t.effectiveArcs, "simulated arcs").c_str(),
        static_cast<long long>(t.otherRows), t.snrMin, t.resolvedMinArcsec, run.modelPath.c_str());
  }
  // Always shown (QUIET too): a calibration without its grid, or with fewer axes, is not the
  // one asked for.
  if (!result.grid.warning.empty()) {
    std::fflush(stdout);
    std::cerr << "WARNING: " << result.grid.warning
              << (run.gridPath.empty() || result.grid.grid ? ""
                                                           : " (" + run.gridPath + " not written)")
              << "\n";
  }
  return 0;
}

}  // namespace octarc
