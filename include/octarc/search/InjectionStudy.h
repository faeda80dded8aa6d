// Completeness and purity of a search on the user's own image, measured by injection
// (`octarc inject`):
//
//   the image as it is --> searched (SearchRun.h, exactly as `octarc search`) --> its
//   candidates: the spurious ones (the image is taken to hold no lens of its own)
//   the image + N simulated lenses (simulation/engine/FieldSimulation.h injectLenses, 30"
//   apart or more, never overlapping) --> searched --> which candidates are injected arcs
//   (InjectionMatch.h: a candidate on a lens rather than its arc is no found arc)
//   --> per selection method (GRID, TREES, or both), as LENS_SCORE's threshold falls through
//   every candidate's score: the injected lenses found (overall, per theta_E and arc-magnitude
//   bin, with Wilson 68.27 % intervals) against the spurious candidates per deg2
//   --> completeness.fits, summary.txt (and stdout), the check-plot, the injected image and
//   the lists the curves were made from, written together.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "octarc/core/Statistics.h"
#include "octarc/plot/CheckPlot.h"
#include "octarc/search/InjectionMatch.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/simulation/engine/FieldSimulation.h"

namespace octarc {

// INJECT_DIR's marker: an existing INJECT_DIR is replaced only when it holds this file.
inline constexpr const char* kInjectMarkerFile = ".octarc-inject";
inline constexpr const char* kInjectMarkerText = "octarc inject output directory\n";

// The bins of the table (the README's study): theta_E < 2", 2-2.5", >= 2.5"; arc magnitude
// < 22, 22-23, >= 23. A bin's lower edge belongs to it.
inline constexpr std::array<double, 2> kThetaEBinEdgesArcsec = {2.0, 2.5};
inline constexpr std::array<double, 2> kArcMagBinEdges = {22.0, 23.0};
inline constexpr int kStudyBins = 3;
// The densities of spurious candidates the summary's table reads the curves at (per deg2).
inline constexpr std::array<double, 4> kSummarySpuriousPerDeg2 = {30.0, 100.0, 400.0, 1000.0};

// One injected system as the curves need it.
struct InjectedSystemScore {
  double thetaEArcsec = 0.0;
  double arcMag = 0.0;
  // The highest LENS_SCORE of the candidates that are its arcs; NaN when none is.
  double bestScore = std::numeric_limits<double>::quiet_NaN();
};

// Found of injected, the fraction and its Wilson 68.27 % interval (NaN, [0, 1] of none).
struct FoundCount {
  std::int64_t found = 0, injected = 0;
  double completeness = std::numeric_limits<double>::quiet_NaN();
  ProportionInterval interval;
};

// The curve at one threshold: candidates with LENS_SCORE >= scoreMin are kept.
struct CompletenessPoint {
  double scoreMin = 0.0;
  std::int64_t spurious = 0;             // candidates of the image as it is
  double spuriousPerDeg2 = 0.0;          // ... per deg2 of its searched area
  std::int64_t spuriousInjected = 0;     // the injected image's candidates that are no injected arc
  double spuriousInjectedPerDeg2 = 0.0;  // (a check on the above)
  FoundCount all;
  std::array<FoundCount, kStudyBins> thetaE, arcMag;
};

// The bin (0, 1, 2) of a value against two edges.
int studyBin(double value, const std::array<double, 2>& edges);

// The curve, one point per distinct LENS_SCORE among the found systems' best scores and both
// spurious lists, the highest first (the last point keeps every candidate). Areas in deg2
// (0: densities NaN).
std::vector<CompletenessPoint> completenessCurve(const std::vector<InjectedSystemScore>& systems,
                                                 const std::vector<double>& spuriousScores,
                                                 double areaDeg2,
                                                 const std::vector<double>& injectedSpuriousScores,
                                                 double injectedAreaDeg2);

// The point of the curve with the lowest threshold whose spurious density is at most
// `perDeg2` (nullopt when even the first exceeds it).
std::optional<CompletenessPoint> pointAtSpuriousDensity(const std::vector<CompletenessPoint>& curve,
                                                        double perDeg2);

struct InjectionStudySettings {
  // The search's configuration, as `octarc search` loads it (the image, the weight map, every
  // key); SCORE_MIN is set to 0 (every threshold is tried) and OUTPUT_DIR is not written.
  SearchRunSettings search;
  // GRID, TREES or both (the grid GRID_NAME, the model MODEL_NAME): one curve each.
  std::vector<SelectionMethod> methods;
  // The injected lenses: lensCount, seed, theta_E range, population. The pixel scale, seeing,
  // zero point, gain and threads are the search's (PIXEL_SCALE or the WCS, SEEING_FWHM,
  // MAG_ZEROPOINT, GAIN or the header's, NTHREADS).
  FieldSimulationSettings injection;
  std::string outDir = "injection";
  PlotDevice plotDevice = PlotDevice::Png;
  RunLog log;  // the run's steps, one line each (none when empty)
};

// A candidate as the lists and curves need it: its best row's position, its score.
struct StudyCandidate {
  double xFits = 0.0, yFits = 0.0;  // X_IMAGE, Y_IMAGE of its best row
  double lensScore = 0.0;
  int system = 0;  // the injected system it is an arc of (0: none; always 0 in the plain image)
};

// One method's searches and curve.
struct MethodCurve {
  SelectionMethod method = SelectionMethod::Grid;
  std::string selectionPath;  // GRID_NAME or MODEL_NAME
  std::vector<StudyCandidate> plainCandidates, injectedCandidates;
  std::vector<InjectedSystemScore> systems;  // by system id
  std::vector<CompletenessPoint> curve;
};

struct InjectionStudy {
  FieldSimulationSettings setup;  // the injection as made (the image's scale, seeing, ...)
  double pixelScaleArcsec = 0.0;
  double areaDeg2 = 0.0, injectedAreaDeg2 = 0.0;  // searched areas
  std::vector<TruthRow> truth;                    // the injected lenses and their images
  std::vector<MethodCurve> methods;
  // The outputs, in outDir.
  std::string tablePath, summaryPath, plotPath, imagePath, truthPath, candidatesPath;
};

// The configuration keys of `octarc inject`: those of search and INJECT_NUMBER, INJECT_SEED,
// INJECT_THETA_MIN, INJECT_THETA_MAX, INJECT_POPULATION, INJECT_DIR and CHECKPLOT_DEV.
std::vector<sexcompat::KeySpec> injectionKeys();

// The settings of a loaded configuration (`run` as the command line resolved it). The methods:
// both when GRID_NAME and MODEL_NAME are both given (in the -c file or on the command line),
// else SELECTION_METHOD's.
InjectionStudySettings injectionSettingsFromConfig(const sexcompat::Config& config,
                                                   RunSettings run);

// Checks the inputs, then searches the image, injects the lenses, searches again and writes
// the outputs into `outDir` (made when missing), all together or none: a failure or an
// interrupt leaves nothing. ConfigError / IoError naming the bad input.
InjectionStudy runInjectionStudy(const InjectionStudySettings& settings);

// The summary: the setup, and per method the completeness at kSummarySpuriousPerDeg2 and at
// every candidate.
void printInjectionSummary(std::ostream& out, const InjectionStudySettings& settings,
                           const InjectionStudy& study);

}  // namespace octarc
