#include "octarc/calibration/CalibrationKeys.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/selection/ColumnExpression.h"
#include "octarc/selection/GridBinning.h"
#include "octarc/selection/TreeModel.h"
#include "octarc/sexcompat/ConvFile.h"
#include "octarc/sexcompat/KeyRow.h"

namespace octarc {

namespace {

using sexcompat::KeySpec;
using Kind = KeySpec::Kind;

using Row = sexcompat::KeyRow;

// The count of a numeric list key (its third value): a whole number from 1 to 1000.
int wholeCount(double value, const char* key) {
  if (!(value >= 1 && value <= 1000 && std::floor(value) == value)) {
    throw ConfigError(std::string(key) +
                      ": the count (third value) must be a whole number from 1 to 1000");
  }
  return int(value);
}

}  // namespace

std::vector<KeySpec> calibrationKeys() {
  std::vector<std::string> types = calibrationPlotTypes();
  std::vector<std::string> names;
  for (const std::string& t : types) names.push_back(lowercase(t));
  KeySpec plotType = Row("CHECKPLOT_TYPE", Kind::Keyword, types,
                         "ARCNESS, ANTIARCNESS, SKEW_MAJOR, SKEW_MINOR, E_IMAGE,\nSNR_ISO, "
                         "LENSING_FRACTION, NOISE_THRESHOLD, THRESHOLD_COUNT,\nSNR_FLOOR, "
                         "COLOUR_CUT, COLOUR_DIFF, GRID_BINNING or NONE")
                         .list(1, 16);
  plotType.keywords = types;
  plotType.keywords.push_back("NONE");
  KeySpec device = Row("CHECKPLOT_DEV", Kind::Keyword, {"PNG"}, "PNG, PDF, SVG, PSC or EPSC");
  device.keywords = {"PNG", "PDF", "SVG", "PSC", "EPSC"};
  KeySpec verbose = Row("VERBOSE_TYPE", Kind::Keyword, {"NORMAL"}, "QUIET or NORMAL");
  verbose.keywords = {"QUIET", "NORMAL"};
  return {
      Row("CALIBRATION_NAME", Kind::String, {"calibration.fits"}, "the calibration tables (FITS)"),
      Row("GRID_NAME", Kind::String, {"arcs.grid.fits"},
          "the occupation-probability grid (FITS); NONE: no grid"),
      Row("MODEL_NAME", Kind::String, {"NONE"},
          "the learned selection's model (FITS; SELECTION_METHOD\nTREES of the search), trained "
          "on the simulated arcs\nagainst SURVEY_CATALOG's rows; NONE: no model"),
      Row("MODEL_SNR_MIN", Kind::Float, {"40"},
          "S/N floor of the rows the model is trained on\n(the search's SNR_MIN)")
          .range(0, 1e30),
      Row("MODEL_RESOLVED_MIN", Kind::Float, {"1.0"},
          "resolved size of those rows, arcsec (the search's\nRESOLVED_MIN)")
          .range(0, 1e6),
      Row("MODEL_TREES", Kind::Int, {"300", "5"}, "boosting rounds and depth of the trees")
          .list(2, 2)
          .range(1, kMaxTreeRoundsOrDepth),
      Row("MODEL_SEED", Kind::Int, {"1"}, "seed of the training (row subsampling)")
          .range(0, 2147483647),
      Row("SEARCH_NAME", Kind::String, {}, "name of the search space of the grid").list(0, 1),
      Row("SEARCH_CUT", Kind::String, {},
          "its cut on the simulated arcs' columns, e.g.\nARCNESS > 0.15 && E_IMAGE > 0.6; "
          "empty: every arc")
          .list(0, 1)
          .expression(),
      Row("GRID_AXES", Kind::String, defaultAxisExpressions(),
          "the grid's axes: expressions on the columns")
          .list(1, 8)
          .expression(),
      Row("GRID_LEVEL", Kind::Float, {"0.99"}, "contour level P of the grid").range(1e-6, 1),
      Row("GRID_NBINS", Kind::Int, {"2", "30"},
          "fewest and most bins per axis tried by the binning\nsearch")
          .list(2, 2)
          .range(2, kMaxBinsPerAxis),
      Row("GRID_TAIL", Kind::Float, {"0.001"}, "fraction left out at each end of an axis range")
          .range(0, 0.499),
      Row("HISTOGRAM_NBINS", Kind::Int, {"40"}, "bins of the distributions").range(1, 10000),
      Row("ELLIP_MIN", Kind::Float, {"0.6"}, "e cut of the distorted arcs (E_IMAGE >)").range(0, 1),
      Row("SNR_MIN", Kind::Float, {"40"}, "S/N cut of reliable arcness (SNR_ISO >)").range(0, 1e30),
      Row("SURVEY_CATALOG", Kind::String, {},
          "octarc detect catalog (FITS_LDAC) for the data side\nof the distributions")
          .list(0, 1),
      Row("NOISE_STUDY", Kind::Bool, {"Y"}, "find the noise-only threshold"),
      Row("NOISE_REALISATIONS", Kind::Int, {"100"}, "noise images").range(1, 100000),
      Row("NOISE_SIZE", Kind::Int, {"512"}, "side of each noise image, pixels").range(16, 16384),
      Row("NOISE_THRESH", Kind::Float, {"0.5", "8", "0.03"},
          "lowest and highest threshold tried and the step\n(sigma)")
          .list(3, 3)
          .range(0, 1000),
      Row("FILTER", Kind::Bool, {"N"},
          "filter the noise images as the survey's detection\n(octarc.sex and simulate lenses: N)"),
      Row("NOISE_SEED", Kind::Int, {"1"}, "seed of the noise images (noise and S/N studies)")
          .range(0, 2147483647),
      Row("THRESHOLD_STUDY", Kind::Bool, {"N"},
          "simulate again for the threshold-count curve\n(THRESHOLD_SYSTEMS per count)"),
      Row("THRESHOLD_SYSTEMS", Kind::Int, {"3000"}, "systems per number of thresholds")
          .range(1, 10000000),
      Row("THRESHOLD_NLEVELS", Kind::Int, {"1", "2", "3", "4", "5", "7", "10", "15", "20", "30"},
          "numbers of thresholds tried")
          .list(1, 64)
          .range(1, 255),
      Row("SNR_STUDY", Kind::Bool, {"N"},
          "simulate again for the S/N floor (arcs scaled to\narcness 0.10, remeasured in noise)"),
      Row("SNR_ARCS", Kind::Int, {"40"}, "arcs remeasured (the first by SYSTEM)").range(1, 100000),
      Row("SNR_ARCNESS", Kind::Float, {"0.05", "0.20"}, "arcness range of the arcs taken")
          .list(2, 2)
          .range(0, 10),
      Row("SNR_NOISE", Kind::Float, {"0.25", "8", "11"},
          "lowest and highest factor of the sky sigma, and\nthe number of factors (log-spaced)")
          .list(3, 3)
          .range(1e-6, 1e6),
      Row("SNR_REALISATIONS", Kind::Int, {"100"}, "noise realisations per factor").range(1, 100000),
      Row("SNR_BINS", Kind::Float, {"5", "1280", "16"},
          "lowest and highest S/N and the number of\n(log-spaced) bins")
          .list(3, 3)
          .range(1e-6, 1e12),
      Row("SNR_RELIABLE", Kind::Float, {"0.01", "0.05"},
          "a reliable bin: |median - 0.10| and 80%-20%\nspread at most these")
          .list(2, 2)
          .range(0, 10),
      Row("SNR_MINPERBIN", Kind::Int, {"20"}, "fewest measurements for a bin to count")
          .range(1, 100000000),
      Row("COLOUR_CUT_MAX", Kind::Float, {"-1", "3", "0.05"},
          "colour cut study (a simulation with --band B): the\nlowest and highest MAX of "
          "COLOUR_CUT B,MAX tried\nand the step (mag)")
          .list(3, 3)
          .range(-100, 100),
      Row("FILTER_NAME", Kind::String, {"default.conv"}, "the survey's detection filter"),
      Row("DETECT_MINAREA", Kind::Int, {"0"},
          "DETECT_MINAREA of the noise study (0: the\nsimulation's)")
          .range(0, 1000000),
      plotType,
      Row("CHECKPLOT_NAME", Kind::String, names,
          "check-plot file names (the device adds the suffix)")
          .list(1, 16),
      device,
      Row("CHECKPLOT_RES", Kind::Int, {"800", "600"}, "check-plot size, pixels")
          .list(2, 2)
          .range(64, 10000),
      verbose,
      Row("NTHREADS", Kind::Int, {"0"}, "number of threads (0 = all cores)").range(0, 1024),
  };
}

CalibrationRun calibrationRunFromConfig(const sexcompat::Config& c,
                                        const SimulationOutput& simulation) {
  CalibrationRun run;
  CalibrationSettings& s = run.settings;
  run.calibrationPath = c.getString("CALIBRATION_NAME");
  run.gridPath = c.getString("GRID_NAME");
  // NONE: the studies alone (no grid is made, and no file written).
  if (run.gridPath == "NONE") {
    run.gridPath.clear();
    s.makeGrid = false;
  }
  if (c.count("SEARCH_CUT") > 0) {
    s.searchSpaceExpression = c.getString("SEARCH_CUT");  // as written (an expression key)
    s.searchSpaceName = c.count("SEARCH_NAME") > 0 ? c.getString("SEARCH_NAME") : "search";
  }
  s.gridAxes = c.getStrings("GRID_AXES");
  // Expressions are checked before any work: they must parse and name columns the systems table
  // has (whether a search space keeps any arc is known once the grid is filled).
  auto requireColumns = [&](const ColumnExpression& e) {
    for (const std::string& name : e.variables()) {
      simulation.systems.requireColumn(name, e.context());
    }
  };
  if (!s.searchSpaceExpression.empty()) {
    requireColumns(
        ColumnExpression(s.searchSpaceExpression, "search space '" + s.searchSpaceName + "'"));
  }
  for (const std::string& axis : s.gridAxes) {
    requireColumns(ColumnExpression(axis, "GRID_AXES " + axis));
  }
  s.gridLevel = c.getDouble("GRID_LEVEL");
  s.minBinsPerAxis = c.getInt("GRID_NBINS", 0);
  s.maxBinsPerAxis = c.getInt("GRID_NBINS", 1);
  if (s.maxBinsPerAxis < s.minBinsPerAxis) {
    throw ConfigError("GRID_NBINS: the fewest bins must not exceed the most");
  }
  s.axisTailFraction = c.getDouble("GRID_TAIL");
  s.histogramBins = c.getInt("HISTOGRAM_NBINS");
  s.fractionCuts.ellipticityMin = c.getDouble("ELLIP_MIN");
  s.fractionCuts.snrMin = c.getDouble("SNR_MIN");
  if (c.count("SURVEY_CATALOG") > 0) run.surveyCatalogPath = c.getString("SURVEY_CATALOG");
  if (c.getString("MODEL_NAME") != "NONE") {
    run.modelPath = c.getString("MODEL_NAME");
    if (run.surveyCatalogPath.empty()) {
      throw ConfigError(
          "MODEL_NAME: training a model needs SURVEY_CATALOG (the objects that are "
          "not lenses)");
    }
    LensModelSettings m;
    m.snrMin = c.getDouble("MODEL_SNR_MIN");
    m.resolvedMinArcsec = c.getDouble("MODEL_RESOLVED_MIN");
    m.trees.rounds = c.getInt("MODEL_TREES", 0);
    m.trees.maxDepth = c.getInt("MODEL_TREES", 1);
    m.trees.seed = std::uint64_t(c.getInt("MODEL_SEED"));
    run.model = m;
  }
  if (c.getBool("NOISE_STUDY")) {
    NoiseThresholdSettings n;
    n.realisations = c.getInt("NOISE_REALISATIONS");
    n.sizePix = c.getInt("NOISE_SIZE");
    n.loSigma = c.getDouble("NOISE_THRESH", 0);
    n.hiSigma = c.getDouble("NOISE_THRESH", 1);
    n.stepSigma = c.getDouble("NOISE_THRESH", 2);
    n.minAreaPix =
        c.getInt("DETECT_MINAREA") > 0 ? c.getInt("DETECT_MINAREA") : simulation.setup.minAreaPix;
    if (c.getBool("FILTER")) {
      n.filter = sexcompat::readConvFile(resolveFilterFile(c.getString("FILTER_NAME")));
    }
    n.threads = c.getInt("NTHREADS");
    n.seed = std::uint64_t(c.getInt("NOISE_SEED"));
    checkNoiseThresholdSettings(n);  // before any work
    s.noise = n;
  }
  if (c.getBool("THRESHOLD_STUDY")) {
    ThresholdCountSettings t;
    t.levelCounts = c.getInts("THRESHOLD_NLEVELS");
    t.systems = c.getInt("THRESHOLD_SYSTEMS");
    t.seed = simulation.setup.seed;
    t.arcnessMin = 0.10;
    t.threads = c.getInt("NTHREADS");
    s.thresholdCount = t;
  }
  if (c.getBool("SNR_STUDY")) {
    SnrFloorSettings f;
    f.arcs = c.getInt("SNR_ARCS");
    f.arcnessMin = c.getDouble("SNR_ARCNESS", 0);
    f.arcnessMax = c.getDouble("SNR_ARCNESS", 1);
    f.noiseFactorLo = c.getDouble("SNR_NOISE", 0);
    f.noiseFactorHi = c.getDouble("SNR_NOISE", 1);
    f.noiseFactorCount = wholeCount(c.getDouble("SNR_NOISE", 2), "SNR_NOISE");
    f.realisations = c.getInt("SNR_REALISATIONS");
    f.snrLo = c.getDouble("SNR_BINS", 0);
    f.snrHi = c.getDouble("SNR_BINS", 1);
    f.snrBinCount = wholeCount(c.getDouble("SNR_BINS", 2), "SNR_BINS");
    f.medianTolerance = c.getDouble("SNR_RELIABLE", 0);
    f.spreadMax = c.getDouble("SNR_RELIABLE", 1);
    f.minPerBin = c.getInt("SNR_MINPERBIN");
    f.seed = std::uint64_t(c.getInt("NOISE_SEED"));
    f.threads = c.getInt("NTHREADS");
    checkSnrFloorSettings(f);  // before any work
    s.snrFloor = f;
  }
  s.colourCut.maxLoMag = c.getDouble("COLOUR_CUT_MAX", 0);
  s.colourCut.maxHiMag = c.getDouble("COLOUR_CUT_MAX", 1);
  s.colourCut.stepMag = c.getDouble("COLOUR_CUT_MAX", 2);
  s.colourCutArcnessMin = 0.10;
  if (!simulation.band.empty()) checkColourCutSettings(s.colourCut);  // before any work
  run.plotDevice = parsePlotDevice(c.getString("CHECKPLOT_DEV"));
  const std::vector<std::string> types = c.getStrings("CHECKPLOT_TYPE");
  // Names pair with types by position when given; otherwise each plot is named after its type.
  std::vector<std::string> names;
  if (c.isExplicit("CHECKPLOT_NAME")) {
    names = c.getStrings("CHECKPLOT_NAME");
  } else {
    for (const std::string& t : types) names.push_back(lowercase(t));
  }
  const bool none = std::find(types.begin(), types.end(), "NONE") != types.end();
  if (!none) {
    if (names.size() != types.size()) {
      throw ConfigError("CHECKPLOT_NAME: " + std::to_string(names.size()) + " names for " +
                        std::to_string(types.size()) + " CHECKPLOT_TYPE values");
    }
    for (std::size_t i = 0; i < types.size(); ++i) {
      if (types[i] == "NOISE_THRESHOLD" && !s.noise) continue;
      if (types[i] == "THRESHOLD_COUNT" && !s.thresholdCount) continue;
      if (types[i] == "SNR_FLOOR" && !s.snrFloor) continue;
      const bool colour = types[i] == "COLOUR_CUT" || types[i] == "COLOUR_DIFF";
      if (colour && simulation.band.empty()) continue;
      run.plots.push_back({types[i], names[i] + plotFileSuffix(run.plotDevice)});
    }
  }
  run.plotWidthPix = c.getInt("CHECKPLOT_RES", 0);
  run.plotHeightPix = c.getInt("CHECKPLOT_RES", 1);
  run.quiet = c.getString("VERBOSE_TYPE") == "QUIET";
  return run;
}

}  // namespace octarc
