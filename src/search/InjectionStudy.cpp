#include "octarc/search/InjectionStudy.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/FitsTable.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/search/InjectionDemo.h"
#include "octarc/search/SearchRun.h"
#include "octarc/sexcompat/KeyRow.h"
#include "octarc/simulation/Population.h"

namespace octarc {

namespace fs = std::filesystem;

int studyBin(double value, const std::array<double, 2>& edges) {
  return value < edges[0] ? 0 : value < edges[1] ? 1 : 2;
}

namespace {

FoundCount foundCount(std::int64_t found, std::int64_t injected) {
  FoundCount c;
  c.found = found;
  c.injected = injected;
  if (injected > 0) c.completeness = double(found) / double(injected);
  c.interval = wilsonInterval(found, injected, 1.0);
  return c;
}

std::int64_t countAtLeast(const std::vector<double>& scores, double threshold) {
  return std::count_if(scores.begin(), scores.end(), [&](double v) { return v >= threshold; });
}

double perDeg2(std::int64_t count, double areaDeg2) {
  return areaDeg2 > 0 ? double(count) / areaDeg2 : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::vector<CompletenessPoint> completenessCurve(const std::vector<InjectedSystemScore>& systems,
                                                 const std::vector<double>& spuriousScores,
                                                 double areaDeg2,
                                                 const std::vector<double>& injectedSpuriousScores,
                                                 double injectedAreaDeg2) {
  std::vector<double> thresholds = spuriousScores;
  thresholds.insert(thresholds.end(), injectedSpuriousScores.begin(), injectedSpuriousScores.end());
  for (const InjectedSystemScore& s : systems) {
    if (!std::isnan(s.bestScore)) thresholds.push_back(s.bestScore);
  }
  std::sort(thresholds.begin(), thresholds.end(), std::greater<double>());
  thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());

  std::vector<CompletenessPoint> curve;
  for (const double t : thresholds) {
    CompletenessPoint p;
    p.scoreMin = t;
    p.spurious = countAtLeast(spuriousScores, t);
    p.spuriousPerDeg2 = perDeg2(p.spurious, areaDeg2);
    p.spuriousInjected = countAtLeast(injectedSpuriousScores, t);
    p.spuriousInjectedPerDeg2 = perDeg2(p.spuriousInjected, injectedAreaDeg2);
    std::int64_t found = 0;
    std::array<std::int64_t, kStudyBins> thetaFound{}, thetaAll{}, magFound{}, magAll{};
    for (const InjectedSystemScore& s : systems) {
      const bool isFound = s.bestScore >= t;  // false for NaN (not found)
      const int tb = studyBin(s.thetaEArcsec, kThetaEBinEdgesArcsec);
      const int mb = studyBin(s.arcMag, kArcMagBinEdges);
      found += isFound;
      thetaFound[tb] += isFound;
      magFound[mb] += isFound;
      ++thetaAll[tb];
      ++magAll[mb];
    }
    p.all = foundCount(found, std::int64_t(systems.size()));
    for (int b = 0; b < kStudyBins; ++b) {
      p.thetaE[b] = foundCount(thetaFound[b], thetaAll[b]);
      p.arcMag[b] = foundCount(magFound[b], magAll[b]);
    }
    curve.push_back(p);
  }
  return curve;
}

std::optional<CompletenessPoint> pointAtSpuriousDensity(const std::vector<CompletenessPoint>& curve,
                                                        double perDeg2Max) {
  std::optional<CompletenessPoint> out;
  for (const CompletenessPoint& p : curve) {
    // A count exactly at the level (3 in 0.03 deg2 at 100 per deg2) may divide to a hair above
    // it: the level is allowed a relative 1e-9. The spurious count only grows down the curve.
    if (p.spuriousPerDeg2 <= perDeg2Max * (1.0 + 1e-9)) out = p;
  }
  return out;
}

namespace {

const char* methodName(SelectionMethod m) {
  return m == SelectionMethod::Trees ? "TREES" : "GRID";
}

// The search of one image by one method, as `octarc search` runs it, keeping every candidate.
SearchRun searchWith(const InjectionStudySettings& s, SelectionMethod method,
                     const std::string& imagePath) {
  SearchRunSettings search = s.search;
  search.run.imagePaths = {imagePath};
  search.search.method = method;
  search.search.scoreMin = 0.0;
  return searchImage(search, RunLog());
}

std::vector<StudyCandidate> studyCandidates(const SearchRun& run,
                                            const std::vector<int>& candidateSystem) {
  const int cx = run.catalog.requireColumn("X_IMAGE", "inject");
  const int cy = run.catalog.requireColumn("Y_IMAGE", "inject");
  std::vector<StudyCandidate> out;
  for (std::size_t i = 0; i < run.result.candidates.size(); ++i) {
    const Candidate& c = run.result.candidates[i];
    StudyCandidate sc;
    sc.xFits = run.catalog.value(std::int64_t(c.row), cx);
    sc.yFits = run.catalog.value(std::int64_t(c.row), cy);
    sc.lensScore = c.lensScore;
    sc.system = candidateSystem.empty() ? 0 : candidateSystem[i];
    out.push_back(sc);
  }
  return out;
}

// Per injected system, the best score of its arcs (NaN when no candidate is one).
std::vector<InjectedSystemScore> systemScores(const InjectionMatch& match,
                                              const std::vector<StudyCandidate>& candidates) {
  std::vector<InjectedSystemScore> out;
  for (const InjectedLensOutcome& o : match.systems) {
    InjectedSystemScore s;
    s.thetaEArcsec = o.einsteinRadiusArcsec;
    s.arcMag = o.arcMag;
    for (const StudyCandidate& c : candidates) {
      if (c.system == o.system && !(c.lensScore <= s.bestScore)) s.bestScore = c.lensScore;
    }
    out.push_back(s);
  }
  return out;
}

std::vector<double> spuriousScoresOf(const std::vector<StudyCandidate>& candidates) {
  std::vector<double> scores;
  for (const StudyCandidate& c : candidates) {
    if (c.system == 0) scores.push_back(c.lensScore);
  }
  return scores;
}

// completeness.fits: one row per method and threshold; its columns declared and filled here.
FitsTable completenessTable(const InjectionStudySettings& s, const InjectionStudy& study) {
  std::vector<std::string> method;
  std::vector<double> scoreMin, spuriousDensity, injectedSpuriousDensity, completeness, low, high;
  std::vector<std::int32_t> spurious, injectedSpurious, found, injected;
  std::vector<std::int32_t> thetaFound, thetaInjected, magFound, magInjected;
  std::vector<double> thetaCompl, thetaLow, thetaHigh, magCompl, magLow, magHigh;
  for (const MethodCurve& m : study.methods) {
    for (const CompletenessPoint& p : m.curve) {
      method.push_back(methodName(m.method));
      scoreMin.push_back(p.scoreMin);
      spurious.push_back(std::int32_t(p.spurious));
      spuriousDensity.push_back(p.spuriousPerDeg2);
      injectedSpurious.push_back(std::int32_t(p.spuriousInjected));
      injectedSpuriousDensity.push_back(p.spuriousInjectedPerDeg2);
      found.push_back(std::int32_t(p.all.found));
      injected.push_back(std::int32_t(p.all.injected));
      completeness.push_back(p.all.completeness);
      low.push_back(p.all.interval.low);
      high.push_back(p.all.interval.high);
      for (int b = 0; b < kStudyBins; ++b) {
        thetaFound.push_back(std::int32_t(p.thetaE[b].found));
        thetaInjected.push_back(std::int32_t(p.thetaE[b].injected));
        thetaCompl.push_back(p.thetaE[b].completeness);
        thetaLow.push_back(p.thetaE[b].interval.low);
        thetaHigh.push_back(p.thetaE[b].interval.high);
        magFound.push_back(std::int32_t(p.arcMag[b].found));
        magInjected.push_back(std::int32_t(p.arcMag[b].injected));
        magCompl.push_back(p.arcMag[b].completeness);
        magLow.push_back(p.arcMag[b].interval.low);
        magHigh.push_back(p.arcMag[b].interval.high);
      }
    }
  }
  auto column = [](std::string name, std::string comment, std::string unit, auto values,
                   int repeat = 1) {
    FitsColumn c;
    c.name = std::move(name);
    c.comment = std::move(comment);
    c.unit = std::move(unit);
    c.repeat = repeat;
    c.values = std::move(values);
    return c;
  };
  const std::string bins = " (3 bins)";
  FitsTable t;
  t.name = "COMPLETENESS";
  t.columns = {
      column("METHOD", "SELECTION_METHOD of the search", "", method, 0),
      column("SCORE_MIN", "candidates kept: LENS_SCORE at least this", "", scoreMin),
      column("SPURIOUS", "candidates of the image as it is", "", spurious),
      column("SPURIOUS_PER_DEG2", "... per deg2 of its searched area", "deg-2", spuriousDensity),
      column("SPURIOUS_INJ", "injected image's candidates that are no injected arc", "",
             injectedSpurious),
      column("SPURIOUS_INJ_PER_DEG2", "... per deg2 (a check)", "deg-2", injectedSpuriousDensity),
      column("FOUND", "injected lenses with an arc among the candidates", "", found),
      column("INJECTED", "injected lenses", "", injected),
      column("COMPLETENESS", "FOUND / INJECTED", "", completeness),
      column("COMPL_LO", "Wilson 68.27% interval, lower bound", "", low),
      column("COMPL_HI", "Wilson 68.27% interval, upper bound", "", high),
      column("FOUND_THETA", "FOUND per theta_E bin" + bins, "", thetaFound, kStudyBins),
      column("INJECTED_THETA", "INJECTED per theta_E bin", "", thetaInjected, kStudyBins),
      column("COMPL_THETA", "COMPLETENESS per theta_E bin", "", thetaCompl, kStudyBins),
      column("COMPL_THETA_LO", "its Wilson lower bounds", "", thetaLow, kStudyBins),
      column("COMPL_THETA_HI", "its Wilson upper bounds", "", thetaHigh, kStudyBins),
      column("FOUND_MAG", "FOUND per arc-magnitude bin" + bins, "", magFound, kStudyBins),
      column("INJECTED_MAG", "INJECTED per arc-magnitude bin", "", magInjected, kStudyBins),
      column("COMPL_MAG", "COMPLETENESS per arc-magnitude bin", "", magCompl, kStudyBins),
      column("COMPL_MAG_LO", "its Wilson lower bounds", "", magLow, kStudyBins),
      column("COMPL_MAG_HI", "its Wilson upper bounds", "", magHigh, kStudyBins),
  };
  const FieldSimulationSettings& f = study.setup;
  t.keywords = {
      FitsKeyword::text("IMAGE", s.search.run.imagePaths.front(), "the image injected into"),
      FitsKeyword::integer("NINJECT", f.lensCount, "lens systems injected"),
      FitsKeyword::integer("SEED", std::int64_t(f.seed), "injection master seed"),
      FitsKeyword::real("THETAMIN", f.minEinsteinRadiusArcsec, "[arcsec] smallest theta_E"),
      FitsKeyword::real("AREA", study.areaDeg2, "[deg2] searched area of the image"),
      FitsKeyword::real("AREAINJ", study.injectedAreaDeg2, "[deg2] ... of the injected image"),
      FitsKeyword::real("PIXSCALE", study.pixelScaleArcsec, "[arcsec] pixel scale"),
      FitsKeyword::real("SEEING", f.seeingFwhmArcsec, "[arcsec] FWHM of the injected PSF"),
      FitsKeyword::real("MAGZERO", f.magZeroPoint, "zero point of the injected light"),
      FitsKeyword::real("GAIN", f.gainElectronsPerAdu, "[e-/ADU] photon noise of the injection"),
      FitsKeyword::real("THETA_E1", kThetaEBinEdgesArcsec[0], "[arcsec] theta_E bin edges"),
      FitsKeyword::real("THETA_E2", kThetaEBinEdgesArcsec[1], "[arcsec]"),
      FitsKeyword::real("MAG1", kArcMagBinEdges[0], "arc-magnitude bin edges"),
      FitsKeyword::real("MAG2", kArcMagBinEdges[1], ""),
      FitsKeyword::real("MATCHRAD", kDemoArcMatchArcsec, "[arcsec] arc to lensed image"),
  };
  return t;
}

Plot completenessPlot(const InjectionStudy& study, const std::string& imagePath) {
  Plot plot;
  plot.title = "Completeness by injection: " + fs::path(imagePath).filename().string();
  plot.xLabel = "spurious candidates per deg#u2#d";
  plot.yLabel = "completeness (68% Wilson interval)";
  // Log x when some point has spurious candidates; a point without any cannot be drawn then.
  for (const MethodCurve& m : study.methods) {
    for (const CompletenessPoint& p : m.curve) plot.logX = plot.logX || p.spuriousPerDeg2 > 0;
  }
  for (const MethodCurve& m : study.methods) {
    PlotSeries series;
    series.label = methodName(m.method);
    for (const CompletenessPoint& p : m.curve) {
      if (plot.logX && !(p.spuriousPerDeg2 > 0)) continue;
      series.x.push_back(p.spuriousPerDeg2);
      series.y.push_back(p.all.completeness);
      series.yLow.push_back(p.all.interval.low);
      series.yHigh.push_back(p.all.interval.high);
    }
    if (series.x.empty() && !plot.logX) {  // no candidate at all: nothing found, none spurious
      series.x = {0.0};
      series.y = {0.0};
    }
    if (!series.x.empty()) plot.series.push_back(series);
  }
  return plot;
}

std::string truthText(const InjectionStudy& study) {
  std::ostringstream o;
  o << "# injected lenses: system kind (1 lens galaxy, 2 lensed image) X_IMAGE Y_IMAGE mag "
       "theta_E_arcsec\n";
  for (const TruthRow& t : study.truth) {
    o << t.systemId << ' ' << int(t.kind) << ' ' << formatNumber(t.xFits, "%.3f") << ' '
      << formatNumber(t.yFits, "%.3f") << ' ' << formatNumber(t.mag, "%.4f") << ' '
      << formatNumber(t.einsteinRadiusArcsec, "%.4f") << '\n';
  }
  return o.str();
}

std::string candidatesText(const InjectionStudy& study) {
  std::ostringstream o;
  o << "# method image (PLAIN: as it is, INJECTED) X_IMAGE Y_IMAGE LENS_SCORE system (0: no "
       "injected arc)\n";
  for (const MethodCurve& m : study.methods) {
    for (const auto& [name, list] :
         {std::pair{"PLAIN", &m.plainCandidates}, std::pair{"INJECTED", &m.injectedCandidates}}) {
      for (const StudyCandidate& c : *list) {
        o << methodName(m.method) << ' ' << name << ' ' << formatNumber(c.xFits, "%.3f") << ' '
          << formatNumber(c.yFits, "%.3f") << ' ' << formatNumber(c.lensScore, "%.17g") << ' '
          << c.system << '\n';
      }
    }
  }
  return o.str();
}

// The injected light needs the image's seeing, zero point and gain (the gain as the search
// reads it: the header's keyword, else GAIN), checked before any search: ConfigError naming the
// key.
void checkInjectionSetup(const RunSettings& run, const ImageHdu& image) {
  const double seeing = run.seeingFwhmArcsec, zeroPoint = run.magZeropoint;
  if (!(seeing > 0.0 && seeing <= 20.0)) {
    throw ConfigError(
        "SEEING_FWHM: the injected lenses need the image's seeing, in (0, 20] "
        "arcsec; got " +
        formatNumber(seeing));
  }
  if (!(zeroPoint > 0.0 && zeroPoint < 50.0)) {
    throw ConfigError(
        "MAG_ZEROPOINT: the injected lenses need the image's zero point, in "
        "(0, 50); got " +
        formatNumber(zeroPoint));
  }
  std::vector<std::string> warnings;
  const std::optional<double> headerGain =
      headerNonNegative(image.header, run.gainKey, run.imagePaths.front(), "GAIN", warnings);
  if (!(headerGain.value_or(run.gainElectronPerAdu) > 0.0)) {
    throw ConfigError(
        "GAIN: the injected light's photon noise needs the image's gain (e-/ADU), "
        "from GAIN or the header's " +
        run.gainKey + " keyword");
  }
}

// The injection's survey: the image's pixel scale and gain as the plain search resolved them.
FieldSimulationSettings injectionSetup(const InjectionStudySettings& s, const SearchRun& plain) {
  FieldSimulationSettings f = s.injection;
  f.pixelScaleArcsec = plain.pixelScaleArcsec;
  f.gainElectronsPerAdu = plain.image.gain;
  f.seeingFwhmArcsec = s.search.run.seeingFwhmArcsec;
  f.magZeroPoint = s.search.run.magZeropoint;
  f.threads = s.search.run.threads;
  return f;
}

}  // namespace

std::vector<sexcompat::KeySpec> injectionKeys() {
  using Row = sexcompat::KeyRow;
  using Kind = sexcompat::KeySpec::Kind;
  std::vector<sexcompat::KeySpec> keys = searchKeys();
  // clang-format off
  const std::vector<sexcompat::KeySpec> own = {
    Row("INJECT_NUMBER", Kind::Int, {"10"}, "simulated lens systems injected (30\" apart)")
        .range(1, 100000),
    Row("INJECT_SEED", Kind::Int, {"1"}, "master random seed of the injection")
        .range(0, 2147483647),
    Row("INJECT_THETA_MIN", Kind::Float, {"1.5"}, "inject lenses of at least this theta_E\n"
        "(arcsec)").range(0, 9.99),
    Row("INJECT_THETA_MAX", Kind::Float, {"0"}, "and at most this one (arcsec; 0: no limit)")
        .range(0, 59.99),
    Row("INJECT_POPULATION", Kind::String, {}, "lens population file of the injected lenses\n"
        "(none: the dls preset)").list(0, 1),
    Row("INJECT_DIR", Kind::String, {"injection"}, "directory of the outputs"),
    Row("CHECKPLOT_DEV", Kind::Keyword, {"PNG"}, "the check-plot's device: PNG, PDF, SVG, PSC\n"
        "or EPSC").keywords({"PNG", "PDF", "SVG", "PSC", "EPSC"}),
  };
  // clang-format on
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

InjectionStudySettings injectionSettingsFromConfig(const sexcompat::Config& c, RunSettings run) {
  InjectionStudySettings s;
  // The lenses are injected into the searched image only: the other bands would hold none.
  for (const char* key : {"COLOUR_IMAGE", "LENS_LIGHT_BAND"}) {
    if (c.count(key) > 0) {
      throw ConfigError(std::string(key) +
                        ": octarc inject injects lenses into the searched image only; "
                        "measure completeness in one band");
    }
  }
  s.search = searchSettingsFromConfig(c, std::move(run));
  if (c.isExplicit("GRID_NAME") && c.isExplicit("MODEL_NAME")) {
    s.methods = {SelectionMethod::Grid, SelectionMethod::Trees};
  } else {
    s.methods = {s.search.search.method};
  }
  FieldSimulationSettings& f = s.injection;
  f.lensCount = c.getInt("INJECT_NUMBER");
  f.seed = std::uint64_t(c.getInt("INJECT_SEED"));
  f.minEinsteinRadiusArcsec = c.getDouble("INJECT_THETA_MIN");
  f.maxEinsteinRadiusArcsec = c.getDouble("INJECT_THETA_MAX");
  if (f.maxEinsteinRadiusArcsec > 0 && f.maxEinsteinRadiusArcsec <= f.minEinsteinRadiusArcsec) {
    throw ConfigError("INJECT_THETA_MAX: must be 0 (no limit) or above INJECT_THETA_MIN");
  }
  if (c.count("INJECT_POPULATION") > 0) f.populationPath = c.getString("INJECT_POPULATION");
  s.outDir = c.getString("INJECT_DIR");
  if (s.outDir.empty()) throw ConfigError("INJECT_DIR: empty");
  s.plotDevice = parsePlotDevice(c.getString("CHECKPLOT_DEV"));
  // The searches write no OUTPUT_DIR; one inside INJECT_DIR keeps search's check of it quiet.
  s.search.outputDir = (fs::path(s.outDir) / "candidates").string();
  return s;
}

InjectionStudy runInjectionStudy(const InjectionStudySettings& s) {
  if (s.methods.empty()) throw ConfigError("inject: no selection method");
  if (s.search.run.imagePaths.size() != 1) throw ConfigError("inject: give one image");
  if (s.injection.lensCount < 1) throw ConfigError("INJECT_NUMBER: inject at least one lens");
  const std::string& imagePath = s.search.run.imagePaths.front();
  InjectionStudy study;
  const fs::path dir(s.outDir);
  study.tablePath = (dir / "completeness.fits").string();
  study.summaryPath = (dir / "summary.txt").string();
  study.plotPath = (dir / (std::string("completeness") + plotFileSuffix(s.plotDevice))).string();
  study.imagePath = (dir / "injected.fits").string();
  study.truthPath = (dir / "injected.truth.txt").string();
  study.candidatesPath = (dir / "candidates.txt").string();
  const std::vector<std::string> outputs = {study.tablePath, study.summaryPath,
                                            study.plotPath,  study.imagePath,
                                            study.truthPath, study.candidatesPath};
  for (const std::string& out : outputs) {
    refuseOutputOverInput(out, "INJECT_DIR", imagePath, "the image");
    refuseOutputOverInput(out, "INJECT_DIR", s.search.run.weightImagePath, "WEIGHT_IMAGE");
    refuseOutputOverInput(out, "INJECT_DIR", s.search.gridPath, "GRID_NAME");
    refuseOutputOverInput(out, "INJECT_DIR", s.search.modelPath, "MODEL_NAME");
  }
  // A user's other directory is never replaced: only an earlier inject's (its marker file).
  AtomicDirectory::checkReplaceable(s.outDir, kInjectMarkerFile, kInjectMarkerText);
  s.injection.validate();
  if (!s.injection.populationPath.empty()) {
    (void)simulation::readPopulationModel(s.injection.populationPath);
  }
  const ImageHdu image = readImage(imagePath);
  // The grid and the model are read now, so that a bad one costs no search.
  for (const SelectionMethod m : s.methods) {
    if (m == SelectionMethod::Trees) {
      (void)loadLensModel(existingUserOrDataFile(s.search.modelPath, "MODEL_NAME file"));
    } else {
      (void)loadGrid(existingUserOrDataFile(s.search.gridPath, "GRID_NAME file"));
    }
  }
  checkInjectionSetup(s.search.run, image);

  // The image as it is, once per method: every candidate is spurious.
  std::vector<SearchRun> plain;
  for (const SelectionMethod m : s.methods) {
    if (s.log) s.log(std::string("> Searching ") + imagePath + " (" + methodName(m) + ")");
    plain.push_back(searchWith(s, m, imagePath));
    MethodCurve curve;
    curve.method = m;
    curve.selectionPath = m == SelectionMethod::Trees ? s.search.modelPath : s.search.gridPath;
    curve.plainCandidates = studyCandidates(plain.back(), {});
    study.methods.push_back(curve);
  }
  study.areaDeg2 = plain.front().result.summary.searchedAreaDeg2;
  study.pixelScaleArcsec = plain.front().pixelScaleArcsec;
  study.setup = injectionSetup(s, plain.front());
  const FieldSimulationSettings& setup = study.setup;
  plain.clear();

  // From here on the outputs are made in a temporary directory beside INJECT_DIR, renamed into
  // place whole at the end: a failure or an interrupt removes it.
  AtomicDirectory outDir(s.outDir, kInjectMarkerFile, kInjectMarkerText);
  const auto inTemp = [&](const std::string& finalPath) {
    return (fs::path(outDir.tempPath()) / fs::path(finalPath).filename()).string();
  };
  if (s.log) s.log("> Injecting " + std::to_string(setup.lensCount) + " lenses");
  const SimulatedField field = injectLenses(image, nullptr, setup);
  for (const TruthRow& t : field.truth) {
    if (t.systemId > 0) study.truth.push_back(t);
  }
  OutputImageHdu hdu;
  hdu.header = field.header;
  hdu.floatPixels = &field.image;
  writeImageFile(inTemp(study.imagePath), {hdu});
  for (MethodCurve& m : study.methods) {
    if (s.log) s.log(std::string("> Searching the injected image (") + methodName(m.method) + ")");
    const SearchRun run = searchWith(s, m.method, inTemp(study.imagePath));
    const InjectionMatch match =
        matchInjectedLenses(study.truth, run.catalog, run.result, run.pixelScaleArcsec, ArcRules(),
                            kDemoArcMatchArcsec, kDemoLensMatchArcsec);
    study.injectedAreaDeg2 = run.result.summary.searchedAreaDeg2;
    m.injectedCandidates = studyCandidates(run, match.candidateSystem);
    m.systems = systemScores(match, m.injectedCandidates);
    std::vector<double> spurious;
    for (const StudyCandidate& c : m.plainCandidates) spurious.push_back(c.lensScore);
    m.curve = completenessCurve(m.systems, spurious, study.areaDeg2,
                                spuriousScoresOf(m.injectedCandidates), study.injectedAreaDeg2);
  }
  writeFitsTables(inTemp(study.tablePath), {completenessTable(s, study)});
  std::ostringstream summary;
  printInjectionSummary(summary, s, study);
  writeTextFile(inTemp(study.summaryPath), summary.str());
  writePlot(inTemp(study.plotPath), s.plotDevice, completenessPlot(study, imagePath));
  writeTextFile(inTemp(study.truthPath), truthText(study));
  writeTextFile(inTemp(study.candidatesPath), candidatesText(study));
  // The marker last: it says the directory is complete.
  writeTextFile((fs::path(outDir.tempPath()) / kInjectMarkerFile).string(), kInjectMarkerText);
  outDir.commit();
  return study;
}

namespace {

std::string fraction(const FoundCount& c) {
  if (c.injected == 0) return "-";
  return std::to_string(c.found) + "/" + std::to_string(c.injected);
}

std::string percentWithInterval(const FoundCount& c) {
  if (c.injected == 0) return "-";
  return formatNumber(100.0 * c.completeness, "%.0f") + "% (" +
         formatNumber(100.0 * c.interval.low, "%.0f") + "-" +
         formatNumber(100.0 * c.interval.high, "%.0f") + ")";
}

void printTableRow(std::ostream& o, const std::string& method, const std::string& level,
                   const std::optional<CompletenessPoint>& p, std::int64_t injected) {
  char line[256];
  if (!p) {
    std::snprintf(line, sizeof line, "  %-6s %-10s %10s %10s %7s %-15s  (no threshold)\n",
                  method.c_str(), level.c_str(), "-", "-",
                  ("0/" + std::to_string(injected)).c_str(), "0%");
    o << line;
    return;
  }
  std::string bins;
  for (const FoundCount& c : p->thetaE) bins += " " + fraction(c);
  bins += " |";
  for (const FoundCount& c : p->arcMag) bins += " " + fraction(c);
  std::snprintf(line, sizeof line, "  %-6s %-10s %10s %10.4g %7s %-15s %s\n", method.c_str(),
                level.c_str(), formatNumber(p->spuriousPerDeg2, "%.1f").c_str(), p->scoreMin,
                fraction(p->all).c_str(), percentWithInterval(p->all).c_str(), bins.c_str());
  o << line;
}

}  // namespace

void printInjectionSummary(std::ostream& o, const InjectionStudySettings& s,
                           const InjectionStudy& study) {
  const FieldSimulationSettings& f = study.setup;
  o << "octarc inject: " << f.lensCount
    << " simulated lenses (theta_E >= " << formatNumber(f.minEinsteinRadiusArcsec) << "\", seed "
    << f.seed << ") injected into " << s.search.run.imagePaths.front() << "\n"
    << "  pixel scale " << formatNumber(study.pixelScaleArcsec, "%.4g") << "\", seeing "
    << formatNumber(f.seeingFwhmArcsec) << "\", zero point " << formatNumber(f.magZeroPoint)
    << ", searched area " << formatNumber(study.areaDeg2, "%.5f") << " deg2 ("
    << formatNumber(study.injectedAreaDeg2, "%.5f") << " injected)\n";
  for (const MethodCurve& m : study.methods) {
    std::int64_t arcs = 0, found = 0;
    for (const StudyCandidate& c : m.injectedCandidates) arcs += c.system > 0;
    for (const InjectedSystemScore& sys : m.systems) found += !std::isnan(sys.bestScore);
    o << "  " << methodName(m.method) << " (" << m.selectionPath
      << "): " << m.plainCandidates.size()
      << " candidate(s) in the image as it is (the spurious ones); " << m.injectedCandidates.size()
      << " in the injected image, " << arcs << " of them arcs of " << found
      << " injected lens(es), " << (std::int64_t(m.injectedCandidates.size()) - arcs) << " other\n";
  }
  o << "\nCompleteness against spurious candidates per deg2 (LENS_SCORE's threshold lowered while\n"
       "the image's own candidates stay at most at the density; Wilson 68.27% intervals;\n"
       "found per theta_E bin <2\", 2-2.5\", >=2.5\" | arc mag <22, 22-23, >=23):\n\n";
  char head[256];
  std::snprintf(head, sizeof head, "  %-6s %-10s %10s %10s %7s %-15s %s\n", "method", "spurious",
                "per deg2", "LENS_SCORE", "found", "completeness", "theta_E bins | mag bins");
  o << head;
  for (const MethodCurve& m : study.methods) {
    const std::int64_t injected = std::int64_t(m.systems.size());
    for (const double level : kSummarySpuriousPerDeg2) {
      printTableRow(o, methodName(m.method), "<= " + formatNumber(level),
                    pointAtSpuriousDensity(m.curve, level), injected);
    }
    printTableRow(o, methodName(m.method), "every cand",
                  m.curve.empty() ? std::nullopt : std::optional(m.curve.back()), injected);
  }
  o << "\nOutputs in " << s.outDir << ":\n"
    << "  completeness.fits  per method and LENS_SCORE threshold: spurious per deg2, found,\n"
    << "                     completeness and its interval, overall and per bin\n"
    << "  " << fs::path(study.plotPath).filename().string()
    << "   completeness against spurious candidates per deg2, one curve per method\n"
    << "  injected.fits      the image with the lenses; injected.truth.txt their positions\n"
    << "  candidates.txt     both images' candidates: position, LENS_SCORE, injected system\n";
}

}  // namespace octarc
