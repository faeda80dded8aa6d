// The configuration of `octarc batch`: its keys (those of search, MATCH_RADIUS, ARRAY_TASK,
// RESTART and TASK) and the settings a loaded configuration gives.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "octarc/batch/BatchConfiguration.h"
#include "octarc/run/RunSettings.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The keys of `octarc batch`: those of search (OUTPUT_DIR names the survey's folder, "survey"
// by default), MATCH_RADIUS, ARRAY_TASK, RESTART and TASK.
std::vector<sexcompat::KeySpec> batchKeys();

// TASK: what a batch does to each tile. SEARCH: `octarc search` (lens candidates, merged into
// the survey's); MEASURE: `octarc measure` on SExtractor's outputs of the tile (its catalog with
// octarc's columns appended, or a new one).
enum class BatchTask { Search, Measure };

// The keys of batchKeys() that one task alone uses: TASK SEARCH the search's own keys (those
// octarc measure has not) and MATCH_RADIUS; TASK MEASURE APPEND_COLUMNS. Setting one for the
// other task has no effect, and gives a warning.
std::vector<std::string> keysOfTaskOnly(BatchTask task);

struct BatchSettings {
  BatchTask task = BatchTask::Search;  // TASK
  std::string manifest;                // a manifest file or a glob of images
  // SEARCH: every tile's search; image, weight, mask, catalog per tile. MEASURE: only `run`,
  // every tile's measure run; image, segmentation image, catalog and weight per tile.
  SearchRunSettings tile;
  // TASK MEASURE: the loaded configuration, which each tile's measure run reads (ASSOC keys).
  std::optional<sexcompat::Config> config;
  // Keys set that this task does not use, "WHERE: -KEY is not used ...", printed by the command.
  std::vector<std::string> warnings;
  std::string outputDir;           // OUTPUT_DIR
  double matchRadiusArcsec = 1.0;  // MATCH_RADIUS: one object in two tiles' overlap
  // ARRAY_TASK: this task's share of a job array, the tiles k (0-based) with k % tasks == task.
  int arrayTask = 0, arrayTasks = 1;
  std::string arrayShareNote;  // how ARRAY_TASK AUTO read Slurm's variables, for the log
  int requestedThreads = 0;    // NTHREADS (0: the machine's cores shared between its ranks)
  // RESTART: when OUTPUT_DIR's tiles were searched with another configuration, set them aside
  // and start over (else that is an error).
  bool restart = false;
  // The configuration the tiles are searched with (batch/BatchConfiguration.h): the keys'
  // values, and the files the search reads (key, path), hashed by the run that checks them.
  std::vector<ConfigurationItem> configuration;
  std::vector<std::pair<std::string, std::string>> configurationFiles;
  // The keys of `configuration` this run leaves at their default (neither the -c file nor the
  // command line sets them): a configuration recorded by an earlier octarc, before such a key
  // existed, is taken to have had it so.
  std::vector<std::string> keysAtDefault;
};

// ConfigError on bad values (and for keys naming a tile's files, which the manifest gives). `run`
// is the detection part as the command line resolved it; its imagePaths hold the manifest.
// ARRAY_TASK AUTO: slurmArrayShare of Slurm's variables.
BatchSettings batchSettingsFromConfig(const sexcompat::Config& config, RunSettings run);

// A job-array task's share of the tiles: the tiles k with k % tasks == task.
struct ArrayShare {
  int task = 0, tasks = 1;
  std::string note;  // what the variables said, for the log; empty outside a job array
};

// ARRAY_TASK AUTO from Slurm's SLURM_ARRAY_TASK_ID, _MIN, _MAX, _STEP and _COUNT (nullptr: not
// set). A task of an evenly spaced array (--array=MIN-MAX:STEP, MAX == MIN + STEP (COUNT - 1))
// takes the share of its position, (ID - MIN) / STEP of COUNT; the shares of all the tasks are
// the whole manifest. The position of a task of any other array (a list such as --array=3,17,
// failed tasks sent again) is not in its variables: it takes the whole manifest, and the tasks
// share the tiles through their claims, each searching the tiles no other has taken. Outside a
// job array (no ID), the whole manifest. Missing MIN, STEP or MAX count as 0, 1 and the value
// of an even array. ConfigError for a value that is not a whole number.
ArrayShare slurmArrayShare(const char* id, const char* min, const char* max, const char* step,
                           const char* count);

}  // namespace octarc
