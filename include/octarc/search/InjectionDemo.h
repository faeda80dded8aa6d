// The demo's run (`octarc demo`): lenses injected into a simulated survey field (or a real
// image), the field searched as `octarc search` does it, and which injected lenses the search
// found.
//
//   simulate field (with injected lenses) --> search in memory (SearchRun.h, octarc.sex: 15
//   levels, MAP_WEIGHT, ASSOC with the truth list; the demo model or grid) --> catalog,
//   candidates, stamps, vetting page --> injected arcs detected and their arcness
//   (simulation/engine/InjectionRecovery.h), the candidates that are injected lenses
//   (InjectionMatch.h) --> the report
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "octarc/core/Progress.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/search/InjectionMatch.h"
#include "octarc/search/SearchRun.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/InjectedField.h"
#include "octarc/simulation/engine/InjectionRecovery.h"

namespace octarc {

// A detected object is one of an injected system's arcs when it lies within this distance of
// one of the system's lensed images in the truth list.
constexpr double kDemoArcMatchArcsec = 2.0;
// The demo shows lenses whose arcs can separate from the lens at ground resolution: most
// systems of the population have Einstein radii below 1", where the lens light swallows them.
constexpr double kDemoMinEinsteinRadiusArcsec = 1.5;
// Arcness above which an object counts as arc-like (METHOD.md section 3).
constexpr double kDemoArcLikeArcness = 0.10;
// A candidate names the right lens when its lens lies this close to the injected one.
constexpr double kDemoLensMatchArcsec = 1.0;

struct InjectionDemoSettings {
  FieldSimulationSettings field;  // the field, or the injected lenses' survey with `real`
  RealImageInput real;            // a real image to inject into instead of a simulated field
  std::string outDir = "out/demo";
  bool trees = true;               // SELECTION_METHOD TREES (the lens model), else GRID (the grid)
  std::string gridPath;            // "": the shipped demo grid
  std::string modelPath;           // "": the shipped demo model
  double snrMin = 40.0;            // the search's SNR_MIN
  std::optional<double> scoreMin;  // SCORE_MIN; default 0.01 with TREES, else 0
  std::optional<double> lensDensityPerDeg2;  // LENS_DENSITY; default the field's injected lenses
  std::string lensLight = "N";               // LENS_LIGHT: N, LOCAL or IMAGE
  ProgressFn simulateProgress, stampProgress;
  RunLog log;  // the run's steps, one line each (none when empty)
};

struct InjectionDemoTimes {
  double simulateSec = 0, searchSec = 0, totalSec = 0;
};

struct InjectionDemo {
  InjectedFieldFiles paths;
  std::string shippedSexPath;  // the search's configuration file
  SimulatedField field;
  SearchRunSettings search;
  SearchRun run;
  InjectionMatch match;
  RecoveryRows rows;  // the catalog's rows as the recovery reads them
  InjectionRecovery recovery;
  InjectionDemoTimes times;
  std::string systemsPath() const;     // per injected lens: theta_E, arc mag, its candidate
  std::string candidatesPath() const;  // per candidate: the injected system it is an arc of
};

// Checks the inputs (the field's settings, the lens model or grid, the population file, the
// outputs against the inputs) before anything is made, then simulates, searches and writes the
// field, its catalog, the candidates and the two injection lists in `outDir`. The outputs are
// provisional until the last is written: a failure or an interrupt removes them all (and the
// directory when the run made it). ConfigError or IoError naming the bad input.
InjectionDemo runInjectionDemo(const InjectionDemoSettings& settings);

// The demo's report: the field, objects per level, the injected arcs detected and their
// arcness, the candidates and which of them are injected lenses, the outputs.
void printInjectionDemoReport(std::ostream& out, const InjectionDemoSettings& settings,
                              const InjectionDemo& demo);

}  // namespace octarc
