// `octarc demo`: the whole method on a simulated survey field, in under two minutes.
//
//   simulate field (with injected lenses) --> detection run in memory (run/DetectionRun.h,
//   octarc.sex: 15 levels, MAP_WEIGHT, ASSOC with the truth list) --> catalog + report: objects per
//   level, injected arcs found and their arcness, arcness of arcs versus everything else

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "octarc/app/Commands.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Interrupt.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/Keys.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

namespace po = boost::program_options;
using simulation::FieldObjectKind;

namespace {

// A detected object is one of an injected system's arcs when it lies within this distance of
// one of the system's lensed images in the truth list (arcs are extended: a piece found at a
// high level can sit well off the image's flux centroid).
constexpr double kArcMatchArcsec = 2.0;
// The catalog's ASSOC radius, pixels: the truth list entry nearest to each object.
constexpr double kAssocRadiusPix = 5.0;
// The demo shows lenses whose arcs can separate from the lens at ground resolution: most
// systems of the population have Einstein radii below 1", where the lens light swallows them.
constexpr double kDemoMinEinsteinRadiusArcsec = 1.5;
// Arcness above which an object counts as arc-like (METHOD.md section 3).
constexpr double kArcLikeArcness = 0.10;

// The columns of the demo catalog that the report reads.
struct CatalogRows {
  std::vector<double> level, threshold, x, y, arcness, size, snr;
  std::size_t rows() const { return level.size(); }
};

// The report's columns of `table`, each value as the catalog stores it (single-precision
// columns rounded to float), rows in catalog order.
CatalogRows reportRows(const Table& table, const std::vector<std::int64_t>& order) {
  auto column = [&](const char* name) {
    const int c = table.findColumn(name);
    if (c < 0) throw Error(std::string("demo: the catalog has no column ") + name);
    const bool single = table.columns()[std::size_t(c)].type == ColumnType::Float32;
    std::vector<double> values;
    for (std::int64_t i = 0; i < table.rows(); ++i) {
      const double v = table.value(order.empty() ? i : order[std::size_t(i)], c);
      values.push_back(single ? double(float(v)) : v);
    }
    return values;
  };
  CatalogRows c;
  c.level = column("THRESH_LEVEL");
  c.threshold = column("THRESHOLD");
  c.x = column("X_IMAGE");
  c.y = column("Y_IMAGE");
  c.arcness = column("ARCNESS");
  c.size = column("SIZE_IMAGE");
  c.snr = column("SNR_ISO");
  return c;
}

// The detection run of step 2: the shipped survey configuration with the demo's own keys on
// top (its columns, the weight map, the truth list as ASSOC list), run in memory.
DetectionRunResult detectField(const std::string& shippedSex,
                               const std::vector<std::pair<std::string, std::string>>& keys,
                               const std::string& imagePath, const std::string& paramPath) {
  std::vector<std::string> warnings;
  const sexcompat::Config config =
      sexcompat::Config::load(sexcompat::octarcMeasureKeys(), shippedSex, keys, &warnings);
  RunSettings settings = settingsFromConfig(config);
  settings.imagePaths = {imagePath};
  settings.configPath = shippedSex;
  settings.parametersPath = paramPath;
  const ColumnPlan columns =
      planColumns(settings, true, int(detectionLevels(settings, 1.0).size()));
  const sexcompat::AssocSettings assoc = sexcompat::AssocSettings::fromConfig(config);
  return runDetection(settings, columns, assoc, RunLog());
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double fractionAbove(const std::vector<double>& v, double cut) {
  if (v.empty()) return std::nan("");
  return double(std::count_if(v.begin(), v.end(), [cut](double a) { return a > cut; })) /
         double(v.size());
}

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

}  // namespace

int runDemo(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  po::options_description options;
  auto add = options.add_options();
  add("help,h", "this help");
  add("size", po::value<int>()->default_value(2048), "field side, pixels");
  add("lenses", po::value<int>()->default_value(12), "injected lens systems");
  add("seed", po::value<std::uint64_t>()->default_value(1), "master random seed");
  add("out", po::value<std::string>()->default_value("out/demo"), "output directory");
  add("threads", po::value<int>()->default_value(0), "worker threads (0 = all cores)");
  add("quiet", "no progress bar");
  po::variables_map vm;
  try {
    // "--lenses=-1" style keeps negative values from being read as options.
    std::vector<std::string> glued;
    for (std::size_t i = 0; i < args.size(); ++i) {
      const bool takesValue = args[i] == "--size" || args[i] == "--lenses" || args[i] == "--seed" ||
                              args[i] == "--out" || args[i] == "--threads";
      if (takesValue && i + 1 < args.size()) {
        glued.push_back(args[i] + "=" + args[i + 1]);
        ++i;
      } else {
        glued.push_back(args[i]);
      }
    }
    po::store(po::command_line_parser(glued).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string(e.what()) + " (see octarc demo -h)");
  }
  if (vm.count("help")) {
    printUsage(options);
    return 0;
  }
  const bool quiet = vm.count("quiet") > 0;
  FieldSimulationSettings s;
  s.sizePix = vm["size"].as<int>();
  s.lensCount = vm["lenses"].as<int>();
  s.seed = vm["seed"].as<std::uint64_t>();
  s.threads = vm["threads"].as<int>();
  s.minEinsteinRadiusArcsec = kDemoMinEinsteinRadiusArcsec;
  s.validate();
  // The shipped survey configuration and columns, found before anything is made.
  const std::string shippedSex = dataFile("octarc.sex");
  const std::string shippedParam = dataFile("octarc.param");

  namespace fs = std::filesystem;
  const fs::path outDir = vm["out"].as<std::string>();
  std::error_code ec;
  const bool madeDir = !fs::exists(outDir, ec);
  fs::create_directories(outDir, ec);
  if (ec || !fs::is_directory(outDir)) {
    throw IoError(outDir.string() + ": cannot create the output directory (" +
                  (ec ? ec.message() : std::string("not a directory")) + ")");
  }
  const FieldOutputPaths paths = FieldOutputPaths::fromImagePath((outDir / "field.fits").string());
  const std::string paramPath = (outDir / "demo.param").string();
  const std::string catalogPath = (outDir / "field.ldac").string();
  // The demo runs in steps, each reading the files of the one before; until the last step is
  // done they are provisional: a failure or an interrupt (core/Interrupt.h) removes them all, and
  // the directory if the demo made it.
  std::vector<int> provisional;
  if (madeDir) provisional.push_back(removeOnInterrupt(outDir.string(), true));
  double simulateSec = 0.0, detectSec = 0.0;
  SimulatedField field;
  DetectionRunResult detection;
  try {
    // 1. The field, and the column list of step 2 (octarc.param's columns plus the truth data
    // of the nearest truth-list entry: id, kind, mag, theta_E, system).
    OutputFiles firstStep;
    addFieldOutputs(firstStep, paths);
    firstStep.add(paramPath);
    for (const std::string& p : {paths.image, paths.weight, paths.truth, paramPath, catalogPath}) {
      provisional.push_back(removeOnInterrupt(p));
    }
    field = simulateField(s, terminalProgress("simulate", "objects", quiet));
    writeSimulatedField(field, s, paths, firstStep);
    firstStep.write(3, [&](const std::string& path) {
      std::ifstream in(shippedParam);
      if (!in) throw IoError(shippedParam + ": cannot read the demo's column list");
      std::ofstream f(path);
      f << in.rdbuf() << "VECTOR_ASSOC(5)          # truth: id, kind, mag, theta_E, system\n"
        << "NUMBER_ASSOC\n";
      if (!f) throw IoError(paramPath + ": write failed");
    });
    firstStep.commit();
    simulateSec = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // 2. Detection and measurement with the survey configuration.
    const std::string assocData =
        std::to_string(kTruthColumnId) + "," + std::to_string(kTruthColumnKind) + "," +
        std::to_string(kTruthColumnMag) + "," + std::to_string(kTruthColumnEinsteinRadius) + "," +
        std::to_string(kTruthColumnSystem);
    const std::vector<std::pair<std::string, std::string>> keys = {
        {"PARAMETERS_NAME", paramPath},
        {"CATALOG_NAME", catalogPath},
        {"CATALOG_TYPE", "FITS_LDAC"},
        {"WEIGHT_TYPE", "MAP_WEIGHT"},
        {"WEIGHT_IMAGE", paths.weight},
        {"ASSOC_NAME", paths.truth},
        {"ASSOC_PARAMS", std::to_string(kTruthColumnX) + "," + std::to_string(kTruthColumnY)},
        {"ASSOC_DATA", assocData},
        {"ASSOC_RADIUS", formatNumber(kAssocRadiusPix, "%.1f", true)},
        {"ASSOC_TYPE", "NEAREST"},
        {"ASSOCSELEC_TYPE", "ALL"},
        {"CHECKIMAGE_TYPE", "NONE"},
        {"NTHREADS", std::to_string(s.threads)},
        {"VERBOSE_TYPE", "QUIET"}};
    if (!quiet) std::cerr << "> Detecting and measuring at 15 levels (octarc detect)\n";
    detection = detectField(shippedSex, keys, paths.image, paramPath);
    OutputFiles catalog;
    catalog.add(catalogPath);
    catalog.write(0, [&](const std::string& path) {
      writeCatalog(path, CatalogType::FitsLdac, detection.parts(), detection.fits10Cards);
    });
    catalog.commit();
    detectSec = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
                simulateSec;
  } catch (...) {
    if (madeDir) {
      fs::remove_all(outDir, ec);
    } else {
      for (const std::string& p : {paths.image, paths.weight, paths.truth, paramPath, catalogPath})
        fs::remove(p, ec);
    }
    throw;
  }
  // Every output is in place: they stay, whatever happens now.
  for (const int slot : provisional) forgetOnInterrupt(slot);

  // 3. The report.
  const CatalogRows cat = reportRows(detection.extensions[0].table, detection.extensions[0].order);
  const double scale = s.pixelScaleArcsec;
  const ArcRules rules;
  int levelCount = 0;
  std::map<int, std::int64_t> perLevel;
  std::map<int, double> levelThresholdAdu;
  for (std::size_t i = 0; i < cat.rows(); ++i) {
    const int l = int(cat.level[i]);
    perLevel[l]++;
    levelThresholdAdu[l] = cat.threshold[i];
    levelCount = std::max(levelCount, l);
  }
  // Truth per system: the lens centre and its images (1-based pixels, as the catalog).
  struct System {
    double lensX = 0, lensY = 0, thetaE = 0;
    std::vector<std::array<double, 2>> images;
    std::int64_t bestRow = -1;
  };
  std::map<int, System> systems;
  for (const TruthRow& r : field.truth) {
    if (r.systemId == 0) continue;
    System& sys = systems[r.systemId];
    sys.thetaE = r.einsteinRadiusArcsec;
    if (r.kind == FieldObjectKind::LensGalaxy) {
      sys.lensX = r.xFits;
      sys.lensY = r.yFits;
    } else {
      sys.images.push_back({r.xFits, r.yFits});
    }
  }
  std::vector<double> arcArcness, otherArcness;
  for (std::size_t i = 0; i < cat.rows(); ++i) {
    const bool resolved = std::sqrt(2.0) * cat.size[i] * scale > rules.minSizeArcsec;
    int arcOf = 0;
    bool nearSystem = false;
    for (auto& [id, sys] : systems) {
      const double fromLens = std::hypot(cat.x[i] - sys.lensX, cat.y[i] - sys.lensY) * scale;
      if (fromLens < sys.thetaE + 2.0 * kArcMatchArcsec) nearSystem = true;
      if (fromLens < rules.minDistanceArcsec || !resolved) continue;
      for (const auto& im : sys.images) {
        if (std::hypot(cat.x[i] - im[0], cat.y[i] - im[1]) * scale < kArcMatchArcsec) arcOf = id;
      }
    }
    if (arcOf && std::isfinite(cat.arcness[i])) {
      arcArcness.push_back(cat.arcness[i]);
      System& sys = systems[arcOf];
      if (sys.bestRow < 0 || cat.arcness[i] > cat.arcness[std::size_t(sys.bestRow)])
        sys.bestRow = std::int64_t(i);
    } else if (!nearSystem && resolved && std::isfinite(cat.arcness[i])) {
      otherArcness.push_back(cat.arcness[i]);
    }
  }

  std::vector<double> bestArcness;
  for (const auto& [id, sys] : systems) {
    if (sys.bestRow >= 0) bestArcness.push_back(cat.arcness[std::size_t(sys.bestRow)]);
  }
  std::ostream& o = std::cout;
  const double fieldArcmin = s.sizePix * scale / 60.0;
  o << "octarc demo: a simulated survey field with " << s.lensCount
    << " injected galaxy-galaxy lenses\n\n"
    << "Field: " << paths.image << "\n  " << s.sizePix << " x " << s.sizePix << " px of " << scale
    << "\" (" << formatNumber(fieldArcmin, "%.1f", true) << "' x "
    << formatNumber(fieldArcmin, "%.1f", true) << "'), seeing " << s.seeingFwhmArcsec << "\", gain "
    << s.gainElectronsPerAdu << " e-/ADU\n"
    << "  sky noise " << formatNumber(field.skySigmaAdu, "%.3f", true)
    << " ADU per pixel (5-sigma limit " << formatNumber(s.limitingMag, "%.1f", true)
    << " mag), chip gap at half weight\n"
    << "  " << field.galaxyCount << " galaxies, " << field.starCount << " stars ("
    << field.saturatedPixels << " saturated pixels), " << systems.size() << " lens systems\n"
    << "  simulated in " << formatNumber(simulateSec, "%.1f", true) << " s\n\n"
    << "Detection: octarc detect -c " << shippedSex << " (" << levelCount
    << " levels, MAP_WEIGHT, ASSOC with the truth list) in "
    << formatNumber(detectSec, "%.1f", true) << " s\n"
    << "  level  threshold [ADU]  objects\n";
  for (const auto& [level, count] : perLevel) {
    char line[80];
    std::snprintf(line, sizeof line, "  %5d  %15.3f  %7lld\n", level, levelThresholdAdu[level],
                  static_cast<long long>(count));
    o << line;
  }
  o << "\nInjected arcs detected: " << bestArcness.size() << " of " << systems.size()
    << " systems (an object >= " << rules.minDistanceArcsec << "\" from the lens, sqrt(2) size > "
    << rules.minSizeArcsec << "\", within " << kArcMatchArcsec
    << "\" of a lensed image, at some level)\n"
    << "  median best ARCNESS " << formatNumber(median(bestArcness), "%.3f", true) << "\n"
    << "  system  theta_E[\"]  best ARCNESS  level     S/N\n";
  for (const auto& [id, sys] : systems) {
    char line[128];
    if (sys.bestRow >= 0) {
      const auto r = std::size_t(sys.bestRow);
      std::snprintf(line, sizeof line, "  %6d  %10.2f  %12.3f  %5d  %6.1f\n", id, sys.thetaE,
                    cat.arcness[r], int(cat.level[r]), cat.snr[r]);
    } else {
      std::snprintf(line, sizeof line, "  %6d  %10.2f  %12s  %5s  %6s\n", id, sys.thetaE,
                    "not found", "-", "-");
    }
    o << line;
  }
  o << "\nArcness (resolved objects, every level):\n"
    << "  injected arcs   " << arcArcness.size() << " rows: median "
    << formatNumber(median(arcArcness), "%.3f", true) << ", "
    << formatNumber(100.0 * fractionAbove(arcArcness, kArcLikeArcness), "%.0f", true) << "% above "
    << kArcLikeArcness << "\n"
    << "  other objects   " << otherArcness.size() << " rows: median "
    << formatNumber(median(otherArcness), "%.3f", true) << ", "
    << formatNumber(100.0 * fractionAbove(otherArcness, kArcLikeArcness), "%.1f", true)
    << "% above " << kArcLikeArcness << "\n\n"
    << "Outputs:\n"
    << "  " << paths.image << "  the image\n"
    << "  " << paths.weight << "  its weight map (MAP_WEIGHT)\n"
    << "  " << paths.truth
    << "  the truth list (an ASSOC list: id x y ra dec kind mag theta_E "
       "system)\n"
    << "  " << catalogPath
    << "  the catalog (FITS_LDAC, every object at every level; VECTOR_ASSOC = truth id, kind, "
       "mag, theta_E, system)\n"
    << "Total "
    << formatNumber(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                    "%.1f", true)
    << " s\n";
  return 0;
}

}  // namespace octarc
