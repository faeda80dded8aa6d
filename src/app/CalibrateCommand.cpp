// `octarc calibrate`: the studies of simulated lenses (METHOD.md section 3) and the occupation
// grid of their arcs (section 4).
//
//   simulate-lenses output(s) [+ survey catalog] --> calibration/Calibration.h
//   --> CALIBRATION_NAME (tables), GRID_NAME (the grid), CHECKPLOT_NAME (check-plots)

#include <cmath>
#include <cstdio>
#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/calibration/Calibration.h"
#include "octarc/calibration/CalibrationKeys.h"
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
         "  -h           this help;  -v  version\n";
}

// The colour cut study: the MAX for each completeness level, then the table every 0.25 mag.
void printColourCut(const ColourCutStudy& c) {
  std::printf("Colour cut COLOUR_CUT %s,MAX on %s (%s; %lld with both colours):\n", c.band.c_str(),
              countWithEffective(c.arcs.count, c.arcs.effective()).c_str(), c.arcSelection.c_str(),
              static_cast<long long>(c.withColours));
  for (const ColourCutLevel& l : c.levels) {
    std::printf("  %3.0f%% of the arcs kept from MAX = %s\n", 100.0 * l.completeness,
                std::isinf(l.maxMag) ? "any" : formatNumber(l.maxMag, "%.3f", true).c_str());
  }
  std::printf("  MAX [mag]  kept\n");
  for (const ColourCutRow& row : c.rows) {
    const double quarters = row.maxMag / 0.25;
    if (std::abs(quarters - std::round(quarters)) > 1e-6) continue;
    std::printf("  %9.2f  %.4f %s\n", row.maxMag, row.fraction.fraction,
                intervalText(row.fraction).c_str());
  }
}

void printSummary(const CalibrationRun& run, const CalibrationResult& r) {
  std::printf("%lld simulated systems, %s with an arc >= 1\" from the lens\n",
              static_cast<long long>(r.simulatedSystems),
              countWithEffective(r.arcSystems.count, r.arcSystems.effective(), "systems").c_str());
  std::printf(
      "Lensing fraction (of the systems with an arc, 68%% intervals):\n  ARCNESS      all         "
      "                e > %g, S/N > %g\n",
      run.settings.fractionCuts.ellipticityMin, run.settings.fractionCuts.snrMin);
  for (std::size_t i = 0; i + 1 < r.fractions.rows.size(); i += 2) {
    const FractionRow& a = r.fractions.rows[i];
    const FractionRow& d = r.fractions.rows[i + 1];
    const std::string range = std::isfinite(a.arcnessHi) ? formatNumber(a.arcnessLo, "%.2f") + "-" +
                                                               formatNumber(a.arcnessHi, "%.2f")
                                                         : "> " + formatNumber(a.arcnessLo, "%.2f");
    std::printf("  %-10s  %.4f %s      %.4f %s\n", range.c_str(), a.fraction.fraction,
                intervalText(a.fraction).c_str(), d.fraction.fraction,
                intervalText(d.fraction).c_str());
  }
  for (const Distribution& d : r.distributions) {
    if (!d.gaussian) continue;
    std::printf("%s of the arcs with %s: Gaussian fit FWHM %s (mean %s)%s\n", d.name.c_str(),
                d.selection.c_str(), formatNumber(d.gaussian->fwhm, "%.3f", true).c_str(),
                formatNumber(d.gaussian->mean, "%.3f", true).c_str(),
                d.gaussian->converged ? "" : ", not converged");
  }
  if (r.noise) {
    std::printf(
        "Noise-only threshold: %s%s sigma (%d realisations of %d^2 pixels, "
        "DETECT_MINAREA %d)\n",
        r.noise->atLowestRung ? "<= " : "",
        formatNumber(r.noise->noiseOnlyThresholdSigma, "%.2f", true).c_str(),
        run.settings.noise->realisations, run.settings.noise->sizePix,
        run.settings.noise->minAreaPix);
  }
  if (r.thresholdCount) {
    std::printf("Arcs with ARCNESS > 0.10 against the number of thresholds (%lld systems each",
                static_cast<long long>(run.settings.thresholdCount->systems));
    if (!r.thresholdCount->rows.empty()) {
      std::printf(", %lld rendered", static_cast<long long>(r.thresholdCount->rows[0].rendered));
    }
    std::printf("):\n");
    for (const ThresholdCountRow& row : r.thresholdCount->rows) {
      std::printf("  %3d levels  %.4f %s  (%s)\n", row.levels, row.fraction.fraction,
                  intervalText(row.fraction).c_str(),
                  countWithEffective(row.withArcness.count, row.withArcness.effective()).c_str());
    }
    std::printf("  flat (within 1 sigma of the most levels) from %d levels\n",
                r.thresholdCount->flattensAtLevels);
  }
  if (r.snrFloor) {
    std::fflush(stdout);
    printSnrFloor(std::cout, *r.snrFloor, *run.settings.snrFloor);
    std::cout.flush();
  }
  if (r.colourCut) printColourCut(*r.colourCut);
  const GridOutcome& g = r.grid;
  const std::string arcs = countWithEffective(g.samples.count, g.samples.effective());
  if (g.skipped) {
    std::printf("Occupation grid: none (GRID_NAME NONE)\n");
  } else if (g.grid) {
    std::printf(
        "Occupation grid: %s, %zu axes, %d bins per axis (finest connected at P = %g), %lld of "
        "%lld occupied bins selected\n",
        arcs.c_str(), g.usedAxes.size(), g.searches.back().result.finestConnected, g.options.level,
        static_cast<long long>(g.grid->contour.selectedBins),
        static_cast<long long>(g.grid->grid.occupiedBins()));
  } else {
    std::printf("Occupation grid: none (%s)\n", arcs.c_str());
  }
}

}  // namespace

int runCalibrate(const std::vector<std::string>& args) {
  std::optional<LoadedConfig> loaded =
      loadConfig(args, "calibrate", calibrationKeys(), printCalibrateUsage, nullptr, false,
                 "simulation file name");
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
  if (!run.quiet) printSummary(run, result);
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
