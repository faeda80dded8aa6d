// The configuration keys of `octarc calibrate` (SExtractor .sex syntax, `-KEY value` on the
// command line, `-d`/`-dd` dumps), and the settings they give for a simulation output.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "octarc/calibration/Calibration.h"
#include "octarc/calibration/LensModelTraining.h"
#include "octarc/plot/CheckPlot.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

std::vector<sexcompat::KeySpec> calibrationKeys();

struct CheckPlotRequest {
  std::string type;  // CHECKPLOT_TYPE
  std::string path;  // CHECKPLOT_NAME + the device's suffix
};

struct CalibrationRun {
  CalibrationSettings settings;
  std::string calibrationPath;             // CALIBRATION_NAME
  std::string gridPath;                    // GRID_NAME; "" for NONE (settings.makeGrid false)
  std::string surveyCatalogPath;           // SURVEY_CATALOG, "" for none
  std::string modelPath;                   // MODEL_NAME; "" for NONE
  std::optional<LensModelSettings> model;  // with modelPath
  PlotDevice plotDevice = PlotDevice::Png;
  std::vector<CheckPlotRequest> plots;
  int plotWidthPix = 800, plotHeightPix = 600;
  bool quiet = false;
};

// The run a configuration asks for; DETECT_MINAREA 0 takes the simulation's. ConfigError for
// inconsistent values (CHECKPLOT_NAME not one per CHECKPLOT_TYPE, a FILTER_NAME that cannot be
// read, ...).
CalibrationRun calibrationRunFromConfig(const sexcompat::Config& config,
                                        const SimulationOutput& simulation);

}  // namespace octarc
