// The configuration of `octarc batch`: its keys (those of search, MATCH_RADIUS and ARRAY_TASK)
// and the settings a loaded configuration gives.
#pragma once

#include <string>
#include <vector>

#include "octarc/run/RunSettings.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The keys of `octarc batch`: those of search (OUTPUT_DIR names the survey's folder, "survey"
// by default), MATCH_RADIUS and ARRAY_TASK.
std::vector<sexcompat::KeySpec> batchKeys();

struct BatchSettings {
  std::string manifest;            // a manifest file or a glob of images
  SearchRunSettings tile;          // every tile's search; image, weight, mask, catalog per tile
  std::string outputDir;           // OUTPUT_DIR
  double matchRadiusArcsec = 1.0;  // MATCH_RADIUS: one object in two tiles' overlap
  // ARRAY_TASK: this task's share of a job array, the tiles k (0-based) with k % tasks == task.
  int arrayTask = 0, arrayTasks = 1;
  int requestedThreads = 0;  // NTHREADS (0: the machine's cores shared between its ranks)
};

// ConfigError on bad values. `run` is the detection part as the command line resolved it; its
// imagePaths hold the manifest. ARRAY_TASK AUTO takes Slurm's SLURM_ARRAY_TASK_ID (less
// SLURM_ARRAY_TASK_MIN) of SLURM_ARRAY_TASK_COUNT when set, else the whole manifest.
BatchSettings batchSettingsFromConfig(const sexcompat::Config& config, RunSettings run);

}  // namespace octarc
