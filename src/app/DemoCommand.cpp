// `octarc demo`: the whole method on a simulated survey field, in under two minutes.
//
//   simulate field (with injected lenses) --> octarc search in memory (search/SearchRun.h,
//   octarc.sex: 15 levels, MAP_WEIGHT, ASSOC with the truth list; the shipped demo grid)
//   --> catalog, candidates, stamps, contact sheet + report: objects per level, injected arcs
//   found and their arcness (simulation/engine/InjectionRecovery.h), the candidates and which
//   injected lenses they are (search/InjectionMatch.h)

#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Interrupt.h"
#include "octarc/core/Progress.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/RunSettings.h"
#include "octarc/search/InjectionMatch.h"
#include "octarc/search/SearchRun.h"
#include "octarc/simulation/Population.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/InjectedField.h"
#include "octarc/simulation/engine/InjectionRecovery.h"

namespace octarc {

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

// A detected object is one of an injected system's arcs when it lies within this distance of
// one of the system's lensed images in the truth list.
constexpr double kArcMatchArcsec = 2.0;
// The demo shows lenses whose arcs can separate from the lens at ground resolution: most
// systems of the population have Einstein radii below 1", where the lens light swallows them.
constexpr double kDemoMinEinsteinRadiusArcsec = 1.5;
// Arcness above which an object counts as arc-like (METHOD.md section 3).
constexpr double kArcLikeArcness = 0.10;
// A candidate names the right lens when its lens lies this close to the injected one.
constexpr double kLensMatchArcsec = 1.0;

struct DemoTimes {
  double simulateSec = 0, searchSec = 0, totalSec = 0;
};

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
               "the contact sheet.\n"
               "\n"
               "--into IMAGE injects the lenses into a real image instead (its own sky, noise\n"
               "and objects; give its --pixel-scale, and --seeing, --mag-zero, --gain for the\n"
               "injected light), searched with --grid or --model (made for that setup).\n"
               "\n"
               "Options:\n"
            << options;
}

// The options; nullopt after -h.
std::optional<po::variables_map> parseDemoOptions(const std::vector<std::string>& args,
                                                  const po::options_description& options) {
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(glueValues(args, options)).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string(e.what()) + " (see octarc demo -h)");
  }
  if (vm.count("help")) {
    printDemoUsage(options);
    return std::nullopt;
  }
  return vm;
}

std::string injectionSystemsPath(const InjectedFieldFiles& paths) {
  return (paths.dir / "injection-systems.txt").string();
}
std::string injectionCandidatesPath(const InjectedFieldFiles& paths) {
  return (paths.dir / "injection-candidates.txt").string();
}

void printCandidates(std::ostream& o, const SearchRun& run, const SearchRunSettings& settings,
                     const InjectionMatch& match) {
  if (settings.search.method == SelectionMethod::Trees) {
    o << "\nSearch: octarc search -SELECTION_METHOD TREES -MODEL_NAME " << settings.modelPath
      << " (SNR_ISO > " << settings.search.snrMin
      << ", resolved, LENS_SCORE >= " << settings.search.scoreMin << ")\n";
  } else {
    o << "\nSearch: octarc search -GRID_NAME " << settings.gridPath << " (SNR_ISO > "
      << settings.search.snrMin << ", resolved, in the grid's contour)\n";
  }
  for (const std::string& w : run.warnings) o << "  note: " << w << "\n";
  for (const std::string& line : searchSummaryLines(run, settings)) o << "  " << line << "\n";
  const std::int64_t spurious = match.spurious();
  o << "  " << (std::int64_t(run.result.candidates.size()) - spurious)
    << " candidate(s) are arcs of injected lenses, " << spurious << " are other objects\n"
    << "Injected lenses:\n"
    << "  system  theta_E    arc mag  candidate  lens right  theta_E estimate\n";
  for (const InjectedLensOutcome& s : match.systems) {
    char line[160];
    std::snprintf(line, sizeof line, "  %6d  %6.2f\"  %8.2f  %9s  %10s  %s\n", s.system,
                  s.einsteinRadiusArcsec, s.arcMag,
                  s.candidate >= 0 ? ("#" + std::to_string(s.candidate + 1)).c_str() : "-",
                  s.candidate < 0 ? "" : (s.lensRight ? "yes" : "no"),
                  s.candidate >= 0 && s.einsteinRadiusEstimateArcsec > 0
                      ? (formatNumber(s.einsteinRadiusEstimateArcsec, "%.2f") + "\"").c_str()
                      : "");
    o << line;
  }
}

void printReport(std::ostream& o, const FieldSimulationSettings& s, const SimulatedField& field,
                 const InjectedFieldFiles& paths, const InjectionRecovery& r,
                 const RecoveryRows& cat, const std::string& shippedSex, const DemoTimes& times,
                 const SearchRun& run, const SearchRunSettings& search, const InjectionMatch& match,
                 const RealImageInput& real) {
  const ArcRules rules;
  const double scale = s.pixelScaleArcsec;
  const std::int64_t width = field.image.width(), height = field.image.height();
  if (real.imagePath.empty()) {
    o << "octarc demo: a simulated survey field with " << s.lensCount
      << " injected galaxy-galaxy lenses\n\n";
  } else {
    o << "octarc demo: " << s.lensCount << " galaxy-galaxy lenses injected into " << real.imagePath
      << "\n\n";
  }
  o << "Field: " << paths.field.image << "\n  " << width << " x " << height << " px of " << scale
    << "\" (" << formatNumber(double(width) * scale / 60.0, "%.1f", true) << "' x "
    << formatNumber(double(height) * scale / 60.0, "%.1f", true) << "'), seeing "
    << s.seeingFwhmArcsec << "\", gain " << s.gainElectronsPerAdu << " e-/ADU\n";
  if (real.imagePath.empty()) {
    o << "  sky noise " << formatNumber(field.skySigmaAdu, "%.3f", true)
      << " ADU per pixel (5-sigma limit " << formatNumber(s.limitingMag, "%.1f", true)
      << " mag), chip gap at half weight\n"
      << "  " << field.galaxyCount << " galaxies, " << field.starCount << " stars ("
      << field.saturatedPixels << " saturated pixels), " << r.systems.size() << " lens systems\n";
  } else {
    o << "  the real image's own sky, noise and objects; zero point " << s.magZeroPoint << ", "
      << r.systems.size() << " lens systems injected\n";
  }
  o << "  simulated in " << formatNumber(times.simulateSec, "%.1f", true) << " s\n\n"
    << "Detection: octarc search -c " << shippedSex << " (" << r.levelCount
    << " levels, MAP_WEIGHT, ASSOC with the truth list), search and outputs in "
    << formatNumber(times.searchSec, "%.1f", true) << " s\n";
  printRecovery(o, r, cat, rules, kArcMatchArcsec, kArcLikeArcness);
  printCandidates(o, run, search, match);
  o << "\nOutputs:\n"
    << "  " << paths.field.image << "  the image\n"
    << "  " << paths.field.weight << "  its weight map (MAP_WEIGHT)\n"
    << "  " << paths.field.truth
    << "  the truth list (an ASSOC list: id x y ra dec kind mag theta_E "
       "system)\n"
    << "  " << paths.catalog
    << "  the catalog (FITS_LDAC, every object at every level; VECTOR_ASSOC = truth id, kind, "
       "mag, theta_E, system)\n"
    << "  " << search.outputDir
    << "/  the candidates (candidates.fits, .cat, .reg), stamps/ and the contact sheet\n"
    << "  " << injectionSystemsPath(paths)
    << "  per injected lens: theta_E, arc mag, its candidate, lens right, theta_E estimate\n"
    << "  " << injectionCandidatesPath(paths)
    << "  per candidate: the injected system it is an arc of (0: none), its spaces, its "
       "LENS_SCORE\n"
    << "Total " << formatNumber(times.totalSec, "%.1f", true) << " s\n"
    << "\nOpen " << search.outputDir << "/index.html in a browser to inspect the candidates.\n";
}

// One line per injected system (scripts/injection-study.py reads them).
void writeInjectionSystems(const std::string& path, const InjectionMatch& match) {
  std::ofstream f(path);
  f << "# system theta_E_arcsec arc_mag candidate spaces lens_right theta_E_estimate_arcsec\n";
  for (const InjectedLensOutcome& s : match.systems) {
    f << s.system << ' ' << formatNumber(s.einsteinRadiusArcsec, "%.4f") << ' '
      << formatNumber(s.arcMag, "%.3f") << ' ' << (s.candidate + 1) << ' ' << s.spaces << ' '
      << (s.lensRight ? 1 : 0) << ' ' << formatNumber(s.einsteinRadiusEstimateArcsec, "%.4f")
      << '\n';
  }
  if (!f) throw IoError(path + ": cannot write");
}

// One line per candidate: the injected system it is an arc of (0: none), its report spaces.
void writeInjectionCandidates(const std::string& path, const InjectionMatch& match,
                              const SearchRun& run) {
  std::ofstream f(path);
  f << "# candidate system spaces lens_score (searched area "
    << formatNumber(run.result.summary.searchedAreaDeg2, "%.8f") << " deg2)\n";
  for (std::size_t i = 0; i < match.candidateSystem.size(); ++i) {
    f << (i + 1) << ' ' << match.candidateSystem[i] << ' ' << run.result.candidates[i].spaces << ' '
      << formatNumber(run.result.candidates[i].lensScore, "%.6e") << '\n';
  }
  if (!f) throw IoError(path + ": cannot write");
}

// The search the demo runs: the shipped configuration, the field's weight map and truth list
// (ASSOC), the shipped demo grid, the candidates into <out>/candidates.
SearchRunSettings demoSearchSettings(const InjectedFieldFiles& paths, const std::string& shippedSex,
                                     const FieldSimulationSettings& s, const std::string& gridPath,
                                     double snrMin, const std::string& lensLight,
                                     const std::vector<std::pair<std::string, std::string>>& more) {
  std::vector<std::pair<std::string, std::string>> keys = recoveryDetectionKeys(paths, s.threads);
  keys.emplace_back("GRID_NAME", gridPath);
  keys.insert(keys.end(), more.begin(), more.end());
  // The survey the field was made for (a real image's without a celestial WCS needs the scale).
  keys.emplace_back("PIXEL_SCALE", formatNumber(s.pixelScaleArcsec, "%.10g"));
  keys.emplace_back("SEEING_FWHM", formatNumber(s.seeingFwhmArcsec, "%.10g"));
  keys.emplace_back("MAG_ZEROPOINT", formatNumber(s.magZeroPoint, "%.10g"));
  keys.emplace_back("GAIN", formatNumber(s.gainElectronsPerAdu, "%.10g"));
  keys.emplace_back("SNR_MIN", formatNumber(snrMin, "%.10g"));
  keys.emplace_back("LENS_LIGHT", lensLight);
  keys.emplace_back("OUTPUT_DIR", (paths.dir / "candidates").string());
  std::vector<std::string> warnings;
  const sexcompat::Config config =
      sexcompat::Config::load(searchKeys(), shippedSex, keys, &warnings);
  RunSettings run = settingsFromConfig(config);
  run.imagePaths = {paths.field.image};
  run.configPath = shippedSex;
  return searchSettingsFromConfig(config, run);
}

}  // namespace

int runDemo(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
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
  const std::optional<po::variables_map> vm = parseDemoOptions(args, options);
  if (!vm) return 0;
  const bool quiet = vm->count("quiet") > 0;
  FieldSimulationSettings s;
  s.sizePix = (*vm)["size"].as<int>();
  s.lensCount = (*vm)["lenses"].as<int>();
  s.seed = (*vm)["seed"].as<std::uint64_t>();
  s.threads = (*vm)["threads"].as<int>();
  s.minEinsteinRadiusArcsec = (*vm)["min-einstein-radius"].as<double>();
  s.maxEinsteinRadiusArcsec = (*vm)["max-einstein-radius"].as<double>();
  if (vm->count("population")) s.populationPath = (*vm)["population"].as<std::string>();
  const std::string lensLight = (*vm)["lens-light"].as<std::string>();
  (void)lenslight::parseSubtractionMode(lensLight);  // checked before anything is made
  if (vm->count("pixel-scale")) s.pixelScaleArcsec = (*vm)["pixel-scale"].as<double>();
  if (vm->count("seeing")) s.seeingFwhmArcsec = (*vm)["seeing"].as<double>();
  if (vm->count("mag-zero")) s.magZeroPoint = (*vm)["mag-zero"].as<double>();
  if (vm->count("gain")) s.gainElectronsPerAdu = (*vm)["gain"].as<double>();
  RealImageInput real;
  if (vm->count("into")) {
    real.imagePath = (*vm)["into"].as<std::string>();
    // A real image's instrument is not the simulated survey's: nothing is assumed.
    for (const char* option : {"pixel-scale", "seeing", "mag-zero", "gain"}) {
      if (!vm->count(option)) {
        throw ConfigError(std::string("--into: give the image's --") + option +
                          " (all of --pixel-scale, --seeing, --mag-zero and --gain)");
      }
    }
  }
  if (vm->count("into-weight")) {
    if (real.imagePath.empty()) throw ConfigError("--into-weight: only with --into");
    real.weightPath = (*vm)["into-weight"].as<std::string>();
  }
  s.validate();
  // The shipped survey configuration and columns, found before anything is made.
  const std::string shippedSex = dataFile("octarc.sex");
  (void)dataFile("octarc.param");
  const std::string method = (*vm)["method"].as<std::string>();
  if (method != "TREES" && method != "GRID") {
    throw ConfigError("--method: TREES or GRID, not '" + method + "'");
  }
  const bool trees = method == "TREES";
  const std::string gridPath =
      vm->count("grid") ? (*vm)["grid"].as<std::string>() : dataFile("demo.grid.fits");
  const std::string modelPath =
      vm->count("model") ? (*vm)["model"].as<std::string>() : dataFile("demo.model.fits");

  // The grid and population are read and the inputs checked against the outputs before anything
  // is made.
  if (trees) {
    (void)loadLensModel(modelPath);
  } else {
    (void)loadGrid(gridPath);
  }
  if (!s.populationPath.empty()) (void)simulation::readPopulationModel(s.populationPath);
  const InjectedFieldFiles paths = makeInjectedFieldDirectory((*vm)["out"].as<std::string>());
  for (const std::string& output : paths.files()) {
    refuseOutputOverInput(output, "--out", real.imagePath, "--into image");
    refuseOutputOverInput(output, "--out", real.weightPath, "--into-weight map");
    refuseOutputOverInput(output, "--out", trees ? modelPath : gridPath,
                          trees ? "--model" : "--grid");
    refuseOutputOverInput(output, "--out", s.populationPath, "--population");
  }
  // Until the last step is done the outputs are provisional: a failure or an interrupt
  // (core/Interrupt.h) removes them all, and the directory if the demo made it.
  std::vector<int> provisional;
  if (paths.madeDir) provisional.push_back(removeOnInterrupt(paths.dir.string(), true));
  for (const std::string& p : paths.files()) provisional.push_back(removeOnInterrupt(p));
  DemoTimes times;
  SimulatedField field;
  SearchRunSettings search;
  SearchRun run;
  InjectionMatch match;
  int candidatesSlot = -1;
  try {
    field = writeInjectedField(s, paths, terminalProgress("simulate", "objects", quiet), real);
    times.simulateSec = seconds();
    // 2. The search, detection and measurement included, in memory; the catalog and the
    // candidates are written from what it returns.
    if (!quiet) {
      std::cerr << "> Searching at 15 levels with the demo " << (trees ? "model" : "grid")
                << " (octarc search)\n";
    }
    // LENS_SCORE's prior: the field's own lens density unless told.
    const double fieldDeg2 =
        double(s.sizePix) * double(s.sizePix) * std::pow(s.pixelScaleArcsec / 3600.0, 2);
    const double lensDensity = vm->count("lens-density") ? (*vm)["lens-density"].as<double>()
                               : s.lensCount > 0         ? double(s.lensCount) / fieldDeg2
                                                         : 1.0;
    std::vector<std::pair<std::string, std::string>> more = {
        {"LENS_DENSITY", formatNumber(lensDensity, "%.10g")},
        {"SCORE_MIN", formatNumber(vm->count("score-min") ? (*vm)["score-min"].as<double>()
                                   : trees                ? 0.01
                                                          : 0.0,
                                   "%.10g")},
        {"SELECTION_METHOD", method}};
    if (trees) more.emplace_back("MODEL_NAME", modelPath);
    search = demoSearchSettings(paths, shippedSex, s, gridPath, (*vm)["snr-min"].as<double>(),
                                lensLight, more);
    run = searchImage(search, RunLog());
    match = matchInjectedLenses(field.truth, run.catalog, run.result, run.pixelScaleArcsec,
                                ArcRules(), kArcMatchArcsec, kLensMatchArcsec);
    OutputFiles outputs;
    outputs.add(paths.catalog);
    outputs.add(injectionSystemsPath(paths));
    outputs.add(injectionCandidatesPath(paths));
    outputs.write(0, [&](const std::string& path) {
      const CatalogPart part{run.image.hdu.header, run.runCards, &run.catalog,
                             run.catalogOrder.empty() ? nullptr : &run.catalogOrder};
      writeCatalog(path, CatalogType::FitsLdac, {part});
    });
    outputs.write(1, [&](const std::string& path) { writeInjectionSystems(path, match); });
    outputs.write(2, [&](const std::string& path) { writeInjectionCandidates(path, match, run); });
    writeSearchOutputs(run, search, terminalProgress("stamps", "stamps", quiet), RunLog());
    // In place under its final name: removed with the rest if what follows fails.
    candidatesSlot = removeTreeOnInterrupt(search.outputDir);
    outputs.commit();
    times.searchSec = seconds() - times.simulateSec;
  } catch (...) {
    std::error_code ec;
    if (paths.madeDir) {
      fs::remove_all(paths.dir, ec);
    } else {
      for (const std::string& p : paths.files()) fs::remove(p, ec);
      if (candidatesSlot >= 0) fs::remove_all(search.outputDir, ec);
    }
    throw;
  }
  // Every output is in place: they stay, whatever happens now.
  for (const int slot : provisional) forgetOnInterrupt(slot);
  forgetOnInterrupt(candidatesSlot);

  // 3. The report.
  const RecoveryRows cat = recoveryRows(run.catalog, run.catalogOrder);
  const InjectionRecovery recovery =
      recoverInjectedArcs(field.truth, cat, s.pixelScaleArcsec, ArcRules(), kArcMatchArcsec);
  times.totalSec = seconds();
  printReport(std::cout, s, field, paths, recovery, cat, shippedSex, times, run, search, match,
              real);
  return 0;
}

}  // namespace octarc
