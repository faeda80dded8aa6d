// `octarc demo`: the whole method on a simulated survey field, in under two minutes.
//
//   simulate field (with injected lenses) --> detection run in memory (run/DetectionRun.h,
//   octarc.sex: 15 levels, MAP_WEIGHT, ASSOC with the truth list) --> catalog + report: objects
//   per level, injected arcs found and their arcness (simulation/engine/InjectionRecovery.h),
//   arcness of arcs versus everything else

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

struct DemoTimes {
  double simulateSec = 0, detectSec = 0, totalSec = 0;
};

void printUsage(const po::options_description& options) {
  std::cout << "Usage: octarc demo [--size 2048] [--lenses 12] [--seed S] [--out DIR] [--quiet]\n"
               "\n"
               "Simulates a survey field with injected galaxy-galaxy lenses (octarc simulate\n"
               "field), detects and measures every object at the 15 thresholds of the shipped\n"
               "octarc.sex (octarc detect, with the weight map and the truth list as an ASSOC\n"
               "list), and reports how many injected arcs were found and their arcness.\n"
               "\n"
               "Options:\n"
            << options;
}

// The options; nullopt after -h.
std::optional<po::variables_map> parseOptions(const std::vector<std::string>& args,
                                              const po::options_description& options) {
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(glueValues(args, options)).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string(e.what()) + " (see octarc demo -h)");
  }
  if (vm.count("help")) {
    printUsage(options);
    return std::nullopt;
  }
  return vm;
}

void printReport(std::ostream& o, const FieldSimulationSettings& s, const SimulatedField& field,
                 const InjectedFieldFiles& paths, const InjectionRecovery& r,
                 const RecoveryRows& cat, const std::string& shippedSex, const DemoTimes& times) {
  const ArcRules rules;
  const double scale = s.pixelScaleArcsec;
  const double fieldArcmin = s.sizePix * scale / 60.0;
  o << "octarc demo: a simulated survey field with " << s.lensCount
    << " injected galaxy-galaxy lenses\n\n"
    << "Field: " << paths.field.image << "\n  " << s.sizePix << " x " << s.sizePix << " px of "
    << scale << "\" (" << formatNumber(fieldArcmin, "%.1f", true) << "' x "
    << formatNumber(fieldArcmin, "%.1f", true) << "'), seeing " << s.seeingFwhmArcsec << "\", gain "
    << s.gainElectronsPerAdu << " e-/ADU\n"
    << "  sky noise " << formatNumber(field.skySigmaAdu, "%.3f", true)
    << " ADU per pixel (5-sigma limit " << formatNumber(s.limitingMag, "%.1f", true)
    << " mag), chip gap at half weight\n"
    << "  " << field.galaxyCount << " galaxies, " << field.starCount << " stars ("
    << field.saturatedPixels << " saturated pixels), " << r.systems.size() << " lens systems\n"
    << "  simulated in " << formatNumber(times.simulateSec, "%.1f", true) << " s\n\n"
    << "Detection: octarc detect -c " << shippedSex << " (" << r.levelCount
    << " levels, MAP_WEIGHT, ASSOC with the truth list) in "
    << formatNumber(times.detectSec, "%.1f", true) << " s\n";
  printRecovery(o, r, cat, rules, kArcMatchArcsec, kArcLikeArcness);
  o << "\nOutputs:\n"
    << "  " << paths.field.image << "  the image\n"
    << "  " << paths.field.weight << "  its weight map (MAP_WEIGHT)\n"
    << "  " << paths.field.truth
    << "  the truth list (an ASSOC list: id x y ra dec kind mag theta_E "
       "system)\n"
    << "  " << paths.catalog
    << "  the catalog (FITS_LDAC, every object at every level; VECTOR_ASSOC = truth id, kind, "
       "mag, theta_E, system)\n"
    << "Total " << formatNumber(times.totalSec, "%.1f", true) << " s\n";
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
  add("quiet", "no progress bar");
  const std::optional<po::variables_map> vm = parseOptions(args, options);
  if (!vm) return 0;
  const bool quiet = vm->count("quiet") > 0;
  FieldSimulationSettings s;
  s.sizePix = (*vm)["size"].as<int>();
  s.lensCount = (*vm)["lenses"].as<int>();
  s.seed = (*vm)["seed"].as<std::uint64_t>();
  s.threads = (*vm)["threads"].as<int>();
  s.minEinsteinRadiusArcsec = kDemoMinEinsteinRadiusArcsec;
  s.validate();
  // The shipped survey configuration and columns, found before anything is made.
  const std::string shippedSex = dataFile("octarc.sex");
  (void)dataFile("octarc.param");

  const InjectedFieldFiles paths = makeInjectedFieldDirectory((*vm)["out"].as<std::string>());
  // Until the last step is done the outputs are provisional: a failure or an interrupt
  // (core/Interrupt.h) removes them all, and the directory if the demo made it.
  std::vector<int> provisional;
  if (paths.madeDir) provisional.push_back(removeOnInterrupt(paths.dir.string(), true));
  for (const std::string& p : paths.files()) provisional.push_back(removeOnInterrupt(p));
  DemoTimes times;
  SimulatedField field;
  DetectionRunResult detection;
  try {
    field = writeInjectedField(s, paths, terminalProgress("simulate", "objects", quiet));
    times.simulateSec = seconds();
    // 2. Detection and measurement with the survey configuration, in memory; the catalog is
    // written from what the run returns.
    if (!quiet) std::cerr << "> Detecting and measuring at 15 levels (octarc detect)\n";
    detection = runConfiguredDetection(paths.field.image, shippedSex,
                                       recoveryDetectionKeys(paths, s.threads));
    OutputFiles catalog;
    catalog.add(paths.catalog);
    catalog.write(0, [&](const std::string& path) {
      writeCatalog(path, CatalogType::FitsLdac, detection.parts(), detection.fits10Cards);
    });
    catalog.commit();
    times.detectSec = seconds() - times.simulateSec;
  } catch (...) {
    std::error_code ec;
    if (paths.madeDir) {
      fs::remove_all(paths.dir, ec);
    } else {
      for (const std::string& p : paths.files()) fs::remove(p, ec);
    }
    throw;
  }
  // Every output is in place: they stay, whatever happens now.
  for (const int slot : provisional) forgetOnInterrupt(slot);

  // 3. The report.
  const RecoveryRows cat =
      recoveryRows(detection.extensions[0].table, detection.extensions[0].order);
  const InjectionRecovery recovery =
      recoverInjectedArcs(field.truth, cat, s.pixelScaleArcsec, ArcRules(), kArcMatchArcsec);
  times.totalSec = seconds();
  printReport(std::cout, s, field, paths, recovery, cat, shippedSex, times);
  return 0;
}

}  // namespace octarc
