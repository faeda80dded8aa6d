// `octarc demo`: the whole method on a simulated survey field, in under two minutes.
//
//   options --> InjectionDemoSettings --> runInjectionDemo (search/InjectionDemo.h: simulate,
//   search, match the injected lenses, write) --> the report on stdout

#include <boost/program_options.hpp>
#include <iostream>

#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/core/Error.h"
#include "octarc/core/Progress.h"
#include "octarc/search/InjectionDemo.h"

namespace octarc {

namespace po = boost::program_options;

namespace {

void printDemoUsage(const po::options_description& options) {
  std::cout << "Usage: octarc demo [--size 2048] [--lenses 12] [--seed S] [--out DIR] [--quiet]\n"
               "\n"
               "Simulates a survey field with injected galaxy-galaxy lenses (octarc simulate\n"
               "field) and searches it (octarc search: every object at the 15 thresholds of the\n"
               "shipped octarc.sex, with the weight map and the truth list as an ASSOC list,\n"
               "selected by the shipped demo lens model, params/demo.model.fits, keeping\n"
               "LENS_SCORE >= 0.01; --method GRID: by the shipped demo grid,\n"
               "params/demo.grid.fits, as the paper did). Reports how many\n"
               "injected arcs were detected and their arcness, the candidates, and which of\n"
               "them are injected lenses; writes the catalog, the candidates, their stamps and\n"
               "the vetting page.\n"
               "\n"
               "--into IMAGE injects the lenses into a real image instead (its own sky, noise\n"
               "and objects; give its --pixel-scale, and --seeing, --mag-zero, --gain for the\n"
               "injected light), searched with --grid or --model (made for that setup).\n"
               "\n"
            << kOptionsAsKeys << "\nOptions:\n"
            << options;
}

po::options_description demoOptions() {
  po::options_description options;
  auto add = options.add_options();
  add("help,h", "this help");
  add("size", po::value<int>()->default_value(2048), "field side, pixels");
  add("lenses", po::value<int>()->default_value(12), "injected lens systems");
  add("seed", po::value<std::uint64_t>()->default_value(1), "master random seed");
  add("out", po::value<std::string>()->default_value("out/demo"), "output directory");
  add("threads", po::value<int>()->default_value(0), "worker threads (0 = all cores)");
  add("into", po::value<std::string>(), "inject the lenses into this real image instead");
  add("into-weight", po::value<std::string>(), "its MAP_WEIGHT weight map (with --into)");
  add("pixel-scale", po::value<double>(), "arcsec per pixel (default 0.257; with --into: needed)");
  add("seeing", po::value<double>(), "PSF FWHM, arcsec (default 0.9)");
  add("mag-zero", po::value<double>(), "magnitude zero point (default 30)");
  add("gain", po::value<double>(), "e-/ADU (default 54)");
  add("method", po::value<std::string>()->default_value("TREES"),
      "SELECTION_METHOD of the search: TREES (the lens model) or GRID (the grid)");
  add("grid", po::value<std::string>(), "occupation grid (default: the shipped demo grid)");
  add("snr-min", po::value<double>()->default_value(40.0), "the search's S/N floor (SNR_MIN)");
  add("model", po::value<std::string>(),
      "lens model (default: the shipped demo model; octarc calibrate -MODEL_NAME)");
  add("score-min", po::value<double>(), "the search's SCORE_MIN (default: 0.01 with TREES, 0)");
  add("lens-density", po::value<double>(),
      "LENS_DENSITY, the prior of LENS_SCORE (default: the injected lenses per deg2, each "
      "counted as an arc; 1 without)");
  add("lens-light", po::value<std::string>()->default_value("N"),
      "the search's LENS_LIGHT: N, LOCAL or IMAGE");
  add("population", po::value<std::string>(),
      "lens population file of the injected lenses (default: the dls preset)");
  add("min-einstein-radius", po::value<double>()->default_value(kDemoMinEinsteinRadiusArcsec),
      "inject lenses of at least this theta_E, arcsec");
  add("max-einstein-radius", po::value<double>()->default_value(0.0),
      "and at most this one (0: no limit)");
  add("quiet", "no progress bar");
  return options;
}

}  // namespace

int runDemo(const std::vector<std::string>& args) {
  const po::options_description options = demoOptions();
  const std::optional<ParsedOptions> parsed = parseOptions(
      args, {"demo", [&] { printDemoUsage(options); }, printCandidateColumns}, options);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->values;
  const bool quiet = vm.count("quiet") > 0;
  InjectionDemoSettings demo;
  FieldSimulationSettings& s = demo.field;
  s.sizePix = vm["size"].as<int>();
  s.lensCount = vm["lenses"].as<int>();
  s.seed = vm["seed"].as<std::uint64_t>();
  s.threads = vm["threads"].as<int>();
  s.minEinsteinRadiusArcsec = vm["min-einstein-radius"].as<double>();
  s.maxEinsteinRadiusArcsec = vm["max-einstein-radius"].as<double>();
  if (vm.count("population")) s.populationPath = vm["population"].as<std::string>();
  demo.lensLight = vm["lens-light"].as<std::string>();
  (void)lenslight::parseSubtractionMode(demo.lensLight);  // checked before anything is made
  if (vm.count("pixel-scale")) s.pixelScaleArcsec = vm["pixel-scale"].as<double>();
  if (vm.count("seeing")) s.seeingFwhmArcsec = vm["seeing"].as<double>();
  if (vm.count("mag-zero")) s.magZeroPoint = vm["mag-zero"].as<double>();
  if (vm.count("gain")) s.gainElectronsPerAdu = vm["gain"].as<double>();
  if (vm.count("into")) {
    demo.real.imagePath = vm["into"].as<std::string>();
    // A real image's instrument is not the simulated survey's: nothing is assumed.
    for (const char* option : {"pixel-scale", "seeing", "mag-zero", "gain"}) {
      if (!vm.count(option)) {
        throw ConfigError(std::string("--into: give the image's --") + option +
                          " (all of --pixel-scale, --seeing, --mag-zero and --gain)");
      }
    }
  }
  if (vm.count("into-weight")) {
    if (demo.real.imagePath.empty()) throw ConfigError("--into-weight: only with --into");
    demo.real.weightPath = vm["into-weight"].as<std::string>();
  }
  const std::string method = vm["method"].as<std::string>();
  if (method != "TREES" && method != "GRID") {
    throw ConfigError("--method: TREES or GRID, not '" + method + "'");
  }
  demo.trees = method == "TREES";
  if (vm.count("grid")) demo.gridPath = vm["grid"].as<std::string>();
  if (vm.count("model")) demo.modelPath = vm["model"].as<std::string>();
  demo.outDir = vm["out"].as<std::string>();
  demo.snrMin = vm["snr-min"].as<double>();
  if (vm.count("score-min")) demo.scoreMin = vm["score-min"].as<double>();
  if (vm.count("lens-density")) demo.lensDensityPerDeg2 = vm["lens-density"].as<double>();
  demo.simulateProgress = terminalProgress("simulate", "objects", quiet);
  demo.stampProgress = terminalProgress("stamps", "stamps", quiet);
  if (!quiet) demo.log = [](const std::string& line) { std::cerr << line << "\n"; };

  const InjectionDemo result = runInjectionDemo(demo);
  printInjectionDemoReport(std::cout, demo, result);
  return 0;
}

}  // namespace octarc
