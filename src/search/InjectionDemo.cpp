#include "octarc/search/InjectionDemo.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "octarc/catalog/Catalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Interrupt.h"
#include "octarc/io/FitsImage.h"
#include "octarc/run/Levels.h"
#include "octarc/run/RunSettings.h"
#include "octarc/simulation/Population.h"

namespace octarc {

namespace {

using DemoKeys = std::vector<std::pair<std::string, std::string>>;

// The search's keys on top of the shipped configuration: the field's weight map and truth list
// (ASSOC), the survey the field was made for, the selection, the candidates into
// <out>/candidates.
DemoKeys demoSearchKeys(const InjectionDemoSettings& s, const InjectedFieldFiles& paths,
                        const std::string& gridPath, const std::string& modelPath) {
  const FieldSimulationSettings& f = s.field;
  DemoKeys keys = recoveryDetectionKeys(paths, f.threads);
  keys.emplace_back("GRID_NAME", gridPath);
  // LENS_SCORE's prior: the field's own lens density unless told, over the image searched (a
  // real image's own size with --into, not --size).
  double widthPix = f.sizePix, heightPix = f.sizePix;
  if (!s.real.imagePath.empty()) {
    const ImageHdu real = readImageHeader(s.real.imagePath);
    widthPix = double(real.widthPix);
    heightPix = double(real.heightPix);
  }
  const double fieldDeg2 = widthPix * heightPix * std::pow(f.pixelScaleArcsec / 3600.0, 2);
  const double lensDensity = s.lensDensityPerDeg2 ? *s.lensDensityPerDeg2
                             : f.lensCount > 0    ? double(f.lensCount) / fieldDeg2
                                                  : 1.0;
  keys.emplace_back("LENS_DENSITY", formatNumber(lensDensity, "%.10g"));
  keys.emplace_back("SCORE_MIN", formatNumber(s.scoreMin ? *s.scoreMin
                                              : s.trees  ? 0.01
                                                         : 0.0,
                                              "%.10g"));
  keys.emplace_back("SELECTION_METHOD", s.trees ? "TREES" : "GRID");
  if (s.trees) keys.emplace_back("MODEL_NAME", modelPath);
  // The survey the field was made for (a real image's without a celestial WCS needs the scale).
  keys.emplace_back("PIXEL_SCALE", formatNumber(f.pixelScaleArcsec, "%.10g"));
  keys.emplace_back("SEEING_FWHM", formatNumber(f.seeingFwhmArcsec, "%.10g"));
  keys.emplace_back("MAG_ZEROPOINT", formatNumber(f.magZeroPoint, "%.10g"));
  keys.emplace_back("GAIN", formatNumber(f.gainElectronsPerAdu, "%.10g"));
  keys.emplace_back("SNR_MIN", formatNumber(s.snrMin, "%.10g"));
  keys.emplace_back("LENS_LIGHT", s.lensLight);
  keys.emplace_back("OUTPUT_DIR", (paths.dir / "candidates").string());
  return keys;
}

SearchRunSettings demoSearchSettings(const DemoKeys& keys, const InjectedFieldFiles& paths,
                                     const std::string& shippedSex) {
  std::vector<std::string> warnings;
  const sexcompat::Config config =
      sexcompat::Config::load(searchKeys(), shippedSex, keys, &warnings);
  RunSettings run = settingsFromConfig(config);
  run.imagePaths = {paths.field.image};
  run.configPath = shippedSex;
  return searchSettingsFromConfig(config, run);
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

// The inputs a run reads, checked before anything is made; the files it writes, which must
// not overwrite any of them.
InjectedFieldFiles checkDemoInputs(const InjectionDemoSettings& s, const std::string& gridPath,
                                   const std::string& modelPath) {
  if (s.trees) {
    (void)loadLensModel(modelPath);
  } else {
    (void)loadGrid(gridPath);
  }
  const std::string& population = s.field.populationPath;
  if (!population.empty()) (void)simulation::readPopulationModel(population);
  InjectedFieldFiles paths = makeInjectedFieldDirectory(s.outDir);
  for (const std::string& output : paths.files()) {
    refuseOutputOverInput(output, "--out", s.real.imagePath, "--into image");
    refuseOutputOverInput(output, "--out", s.real.weightPath, "--into-weight map");
    refuseOutputOverInput(output, "--out", s.trees ? modelPath : gridPath,
                          s.trees ? "--model" : "--grid");
    refuseOutputOverInput(output, "--out", population, "--population");
  }
  return paths;
}

// Simulates the field, searches it and writes every output; the times since `start`.
void simulateSearchWrite(const InjectionDemoSettings& s, const DemoKeys& keys, InjectionDemo& demo,
                         int& candidatesSlot, std::chrono::steady_clock::time_point start) {
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const InjectedFieldFiles& paths = demo.paths;
  demo.field = writeInjectedField(s.field, paths, s.simulateProgress, s.real);
  demo.times.simulateSec = seconds();
  // The search, detection and measurement included, in memory; the catalog and the
  // candidates are written from what it returns.
  demo.search = demoSearchSettings(keys, paths, demo.shippedSexPath);
  if (s.log) {
    s.log("> Searching at " + std::to_string(detectionLevels(demo.search.run, 1.0).size()) +
          " levels with the demo " + (s.trees ? "model" : "grid") + " (octarc search)");
  }
  demo.run = searchImage(demo.search, RunLog());
  const SearchRun& run = demo.run;
  demo.match = matchInjectedLenses(demo.field.truth, run.catalog, run.result, run.pixelScaleArcsec,
                                   ArcRules(), kDemoArcMatchArcsec, kDemoLensMatchArcsec);
  OutputFiles outputs;
  outputs.add(paths.catalog);
  outputs.add(demo.systemsPath());
  outputs.add(demo.candidatesPath());
  outputs.write(0, [&](const std::string& path) {
    const CatalogPart part{run.image.hdu.header, run.runCards, &run.catalog,
                           run.catalogOrder.empty() ? nullptr : &run.catalogOrder};
    writeCatalog(path, CatalogType::FitsLdac, {part});
  });
  outputs.write(1, [&](const std::string& path) { writeInjectionSystems(path, demo.match); });
  outputs.write(2,
                [&](const std::string& path) { writeInjectionCandidates(path, demo.match, run); });
  writeSearchOutputs(run, demo.search, s.stampProgress, RunLog());
  // In place under its final name: removed with the rest if what follows fails.
  candidatesSlot = removeTreeOnInterrupt(demo.search.outputDir);
  outputs.commit();
  demo.times.searchSec = seconds() - demo.times.simulateSec;
}

}  // namespace

std::string InjectionDemo::systemsPath() const {
  return (paths.dir / "injection-systems.txt").string();
}

std::string InjectionDemo::candidatesPath() const {
  return (paths.dir / "injection-candidates.txt").string();
}

InjectionDemo runInjectionDemo(const InjectionDemoSettings& s) {
  const auto start = std::chrono::steady_clock::now();
  (void)lenslight::parseSubtractionMode(s.lensLight);
  s.field.validate();
  InjectionDemo demo;
  // The shipped survey configuration and columns, found before anything is made.
  demo.shippedSexPath = dataFile("octarc.sex");
  (void)dataFile("octarc.param");
  const std::string gridPath = s.gridPath.empty() ? dataFile("demo.grid.fits") : s.gridPath;
  const std::string modelPath = s.modelPath.empty() ? dataFile("demo.model.fits") : s.modelPath;
  demo.paths = checkDemoInputs(s, gridPath, modelPath);
  const DemoKeys keys = demoSearchKeys(s, demo.paths, gridPath, modelPath);

  // Until the last step is done the outputs are provisional: a failure or an interrupt
  // (core/Interrupt.h) removes them all, and the directory if the demo made it.
  std::vector<int> provisional;
  if (demo.paths.madeDir) provisional.push_back(removeOnInterrupt(demo.paths.dir.string(), true));
  for (const std::string& p : demo.paths.files()) provisional.push_back(removeOnInterrupt(p));
  int candidatesSlot = -1;
  try {
    simulateSearchWrite(s, keys, demo, candidatesSlot, start);
  } catch (...) {
    std::error_code ec;
    if (demo.paths.madeDir) {
      std::filesystem::remove_all(demo.paths.dir, ec);
    } else {
      for (const std::string& p : demo.paths.files()) std::filesystem::remove(p, ec);
      if (candidatesSlot >= 0) std::filesystem::remove_all(demo.search.outputDir, ec);
    }
    throw;
  }
  // Every output is in place: they stay, whatever happens now.
  for (const int slot : provisional) forgetOnInterrupt(slot);
  forgetOnInterrupt(candidatesSlot);

  demo.rows = recoveryRows(demo.run.catalog, demo.run.catalogOrder);
  demo.recovery = recoverInjectedArcs(demo.field.truth, demo.rows, s.field.pixelScaleArcsec,
                                      ArcRules(), kDemoArcMatchArcsec);
  demo.times.totalSec =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return demo;
}

namespace {

void printDemoCandidates(std::ostream& o, const InjectionDemo& demo) {
  const SearchRun& run = demo.run;
  const SearchRunSettings& settings = demo.search;
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
  const std::int64_t spurious = demo.match.spurious();
  o << "  " << (std::int64_t(run.result.candidates.size()) - spurious)
    << " candidate(s) are arcs of injected lenses, " << spurious << " are other objects\n"
    << "Injected lenses:\n"
    << "  system  theta_E    arc mag  candidate  lens right  theta_E estimate\n";
  for (const InjectedLensOutcome& s : demo.match.systems) {
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

void printDemoField(std::ostream& o, const InjectionDemoSettings& settings,
                    const InjectionDemo& demo) {
  const FieldSimulationSettings& s = settings.field;
  const SimulatedField& field = demo.field;
  const double scale = s.pixelScaleArcsec;
  const std::int64_t width = field.image.width(), height = field.image.height();
  o << "Field: " << demo.paths.field.image << "\n  " << width << " x " << height << " px of "
    << scale << "\" (" << formatNumber(double(width) * scale / 60.0, "%.1f", true) << "' x "
    << formatNumber(double(height) * scale / 60.0, "%.1f", true) << "'), seeing "
    << s.seeingFwhmArcsec << "\", gain " << s.gainElectronsPerAdu << " e-/ADU\n";
  if (settings.real.imagePath.empty()) {
    o << "  sky noise " << formatNumber(field.skySigmaAdu, "%.3f", true)
      << " ADU per pixel (5-sigma limit " << formatNumber(s.limitingMag, "%.1f", true)
      << " mag), chip gap at half weight\n"
      << "  " << field.galaxyCount << " galaxies, " << field.starCount << " stars ("
      << field.saturatedPixels << " saturated pixels), " << demo.recovery.systems.size()
      << " lens systems\n";
  } else {
    o << "  the real image's own sky, noise and objects; zero point " << s.magZeroPoint << ", "
      << demo.recovery.systems.size() << " lens systems injected\n";
  }
}

void printDemoOutputs(std::ostream& o, const InjectionDemo& demo) {
  const InjectedFieldFiles& paths = demo.paths;
  o << "\nOutputs:\n"
    << "  " << paths.field.image << "  the image\n"
    << "  " << paths.field.weight << "  its weight map (MAP_WEIGHT)\n"
    << "  " << paths.field.truth
    << "  the truth list (an ASSOC list: id x y ra dec kind mag theta_E "
       "system)\n"
    << "  " << paths.catalog
    << "  the catalog (FITS_LDAC, every object at every level; VECTOR_ASSOC = truth id, kind, "
       "mag, theta_E, system)\n"
    << "  " << demo.search.outputDir
    << "/  the candidates (candidates.fits, .cat, .reg), stamps/ and the vetting page\n"
    << "  " << demo.systemsPath()
    << "  per injected lens: theta_E, arc mag, its candidate, lens right, theta_E estimate\n"
    << "  " << demo.candidatesPath()
    << "  per candidate: the injected system it is an arc of (0: none), its spaces, its "
       "LENS_SCORE\n";
}

}  // namespace

void printInjectionDemoReport(std::ostream& o, const InjectionDemoSettings& settings,
                              const InjectionDemo& demo) {
  const std::string& real = settings.real.imagePath;
  if (real.empty()) {
    o << "octarc demo: a simulated survey field with " << settings.field.lensCount
      << " injected galaxy-galaxy lenses\n\n";
  } else {
    o << "octarc demo: " << settings.field.lensCount << " galaxy-galaxy lenses injected into "
      << real << "\n\n";
  }
  printDemoField(o, settings, demo);
  o << "  simulated in " << formatNumber(demo.times.simulateSec, "%.1f", true) << " s\n\n"
    << "Detection: octarc search -c " << demo.shippedSexPath << " (" << demo.recovery.levelCount
    << " levels, MAP_WEIGHT, ASSOC with the truth list), search and outputs in "
    << formatNumber(demo.times.searchSec, "%.1f", true) << " s\n";
  printRecovery(o, demo.recovery, demo.rows, ArcRules(), kDemoArcMatchArcsec, kDemoArcLikeArcness);
  printDemoCandidates(o, demo);
  printDemoOutputs(o, demo);
  o << "Total " << formatNumber(demo.times.totalSec, "%.1f", true) << " s\n"
    << "\nOpen " << demo.search.outputDir
    << "/index.html in a browser to inspect the candidates.\n";
}

}  // namespace octarc
