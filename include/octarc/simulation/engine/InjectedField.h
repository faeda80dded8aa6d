// A simulated survey field with injected lenses, written to a directory with what a detection
// run needs to recover them: the column list (octarc.param plus the truth data of the nearest
// truth-list entry, VECTOR_ASSOC = id, kind, mag, theta_E, system) and the configuration keys
// (the weight map, the truth list as ASSOC list). The demo runs it; injection-recovery studies
// build on it.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "octarc/core/Progress.h"
#include "octarc/simulation/engine/FieldSimulation.h"

namespace octarc {

struct InjectedFieldFiles {
  std::filesystem::path dir;
  bool madeDir = false;  // the run made `dir` (and removes it on failure)
  FieldOutputPaths field;
  std::string param, catalog;
  std::vector<std::string> files() const {
    return {field.image, field.weight, field.truth, param, catalog};
  }
};

// The file names in `dir` (field.fits, field.weight.fits, field.truth.txt, demo.param,
// field.ldac), making the directory when it does not exist; IoError when it cannot be made.
InjectedFieldFiles makeInjectedFieldDirectory(const std::filesystem::path& dir);

// A real image to inject the lenses into instead of simulating a field (`octarc demo --into`):
// its path and, optionally, its MAP_WEIGHT weight map.
struct RealImageInput {
  std::string imagePath;   // "" = simulate a field
  std::string weightPath;  // "" = none (a uniform weight map is written)
};

// Simulates the field (or injects the lenses into `real`), writes the image, its weight map,
// the truth list and the column list; they appear together (or not at all).
SimulatedField writeInjectedField(const FieldSimulationSettings& settings,
                                  const InjectedFieldFiles& files, const ProgressFn& progress,
                                  const RealImageInput& real = {});

// The configuration keys (KEY, value) of the recovery run on top of a survey .sex file: the
// column list, catalog name, MAP_WEIGHT with the weight map, ASSOC with the truth list (nearest
// entry within 5 pixels, every row kept), no check-image, `threads`, quiet.
std::vector<std::pair<std::string, std::string>> recoveryDetectionKeys(
    const InjectedFieldFiles& files, int threads);

}  // namespace octarc
