#include "octarc/batch/BatchKeys.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/run/RunKeys.h"
#include "octarc/sexcompat/KeyRow.h"

namespace octarc {

namespace {

using sexcompat::KeySpec;
using Kind = KeySpec::Kind;

// A Slurm variable's value: nothing when not set; ConfigError unless a whole number that an int
// holds.
std::optional<long long> slurmNumber(const char* name, const char* value) {
  if (value == nullptr) return std::nullopt;
  const std::string text = value;
  try {
    std::size_t used = 0;
    const long long n = std::stoll(text, &used);
    if (used == text.size() && n >= 0 && n <= std::numeric_limits<int>::max()) return n;
  } catch (const std::exception&) {
  }
  throw ConfigError(std::string("ARRAY_TASK AUTO: ") + name + " " + quoteForMessage(text) +
                    " is not a whole number from 0 to " +
                    std::to_string(std::numeric_limits<int>::max()));
}

}  // namespace

ArrayShare slurmArrayShare(const char* id, const char* min, const char* max, const char* step,
                           const char* count) {
  const std::optional<long long> taskId = slurmNumber("SLURM_ARRAY_TASK_ID", id);
  if (!taskId) return {};  // not a task of a job array
  const std::optional<long long> first = slurmNumber("SLURM_ARRAY_TASK_MIN", min);
  const std::optional<long long> last = slurmNumber("SLURM_ARRAY_TASK_MAX", max);
  const std::optional<long long> spacing = slurmNumber("SLURM_ARRAY_TASK_STEP", step);
  const std::optional<long long> tasks = slurmNumber("SLURM_ARRAY_TASK_COUNT", count);
  const std::string task = "Slurm array task " + std::to_string(*taskId);
  const std::string shared =
      ": the whole manifest, shared with the other tasks through the tiles' claims";
  if (!tasks) return {0, 1, task + " without SLURM_ARRAY_TASK_COUNT" + shared};
  const long long from = first.value_or(0), by = spacing.value_or(1);
  const long long to = last.value_or(from + by * (*tasks - 1));
  const std::string range = "--array=" + std::to_string(from) + "-" + std::to_string(to) +
                            (by != 1 ? ":" + std::to_string(by) : "") + " ";
  // The ids of an evenly spaced array are MIN, MIN + STEP, ... MAX: COUNT of them.
  const bool even = *tasks >= 1 && by >= 1 && to == from + by * (*tasks - 1) && *taskId >= from &&
                    (*taskId - from) % by == 0 && (*taskId - from) / by < *tasks;
  if (!even) {
    return {0, 1,
            task + ", one of " + std::to_string(*tasks) + " ids from " + std::to_string(from) +
                " to " + std::to_string(to) + " that are not a range with step " +
                std::to_string(by) + shared};
  }
  const int position = int((*taskId - from) / by);
  return {position, int(*tasks),
          task + " (" + range + "of " + std::to_string(*tasks) + " tasks): share " +
              std::to_string(position) + "/" + std::to_string(*tasks)};
}

std::vector<KeySpec> batchKeys() {
  std::vector<KeySpec> keys = searchKeys();
  for (KeySpec& k : keys) {
    if (k.name == "OUTPUT_DIR") {
      k.defaults = {"survey"};
      k.comment = "directory of the survey: journal, tiles/, candidates";
    } else if (k.name == "LENS_CHECKIMAGES") {
      k.defaults = {"N"};  // two image-sized files per tile: only when asked for
    } else if (k.name == "WEIGHT_IMAGE") {
      // Each tile's comes from the manifest: none here, so that a -dd template loads back.
      k.defaults = {};
      k.comment = "none: each tile's weight map is in the manifest";
    } else if (k.name == "CATALOG_TYPE") {
      k.comment =
          "format of the survey's OUTPUT_DIR/candidates.fits:\nFITS_LDAC, FITS_1.0, ASCII_HEAD, "
          "ASCII or\nASCII_VOTABLE (the tiles' stay FITS_LDAC); TASK MEASURE\nwith "
          "APPEND_COLUMNS N: format of each tile's catalog";
    } else if (k.name == "APPEND_COLUMNS") {
      k.comment =
          "TASK MEASURE: Y appends octarc's columns to each\ntile's CATALOG (its format kept), N "
          "writes a new\ncatalog (CATALOG_TYPE)";
    }
  }
  // clang-format off
  const std::vector<KeySpec> own = {
    sexcompat::KeyRow("MATCH_RADIUS", Kind::Float, {"1.0"}, "candidates of two tiles closer than "
        "this are one\n(arcsec)").range(0, 60),
    sexcompat::KeyRow("ARRAY_TASK", Kind::String, {"AUTO"}, "this job-array task's share: I/N "
        "(tiles k with\nk % N == I), AUTO (from Slurm's SLURM_ARRAY_TASK_*)"),
    sexcompat::KeyRow("RESTART", Kind::Bool, {"N"}, "Y: when OUTPUT_DIR's tiles were searched "
        "with another\nconfiguration, set them aside (OUTPUT_DIR/earlier-N)\nand start over; N: "
        "that is an error"),
    sexcompat::KeyRow("TASK", Kind::Keyword, {"SEARCH"}, "SEARCH: search each tile for lens "
        "candidates;\nMEASURE: octarc measure on each tile's SExtractor\noutputs (manifest "
        "rows IMAGE SEGMENTATION CATALOG\n[WEIGHT])").keywords({"SEARCH", "MEASURE"}),
  };
  // clang-format on
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

std::vector<std::string> keysOfTaskOnly(BatchTask task) {
  if (task == BatchTask::Measure) return {"APPEND_COLUMNS"};
  std::set<std::string> measureKeys;
  for (const KeySpec& k : octarcKeys()) measureKeys.insert(k.name);
  std::vector<std::string> keys;
  for (const KeySpec& k : batchKeys()) {
    if (k.ignored || measureKeys.count(k.name)) continue;
    if (k.name == "OUTPUT_DIR" || k.name == "ARRAY_TASK" || k.name == "RESTART" ||
        k.name == "TASK") {
      continue;  // every task's
    }
    keys.push_back(k.name);
  }
  return keys;
}

namespace {

// "WHERE: -KEY is not used with TASK T ..." for each key of the other task that is set on the
// command line, or in the file to another value than its default (a -dd template lists every
// key), as for the keys octarc ignores.
std::vector<std::string> otherTaskKeyWarnings(const sexcompat::Config& c, BatchTask task) {
  const BatchTask other = task == BatchTask::Search ? BatchTask::Measure : BatchTask::Search;
  const char* taskName = task == BatchTask::Search ? "SEARCH" : "MEASURE";
  const char* otherName = task == BatchTask::Search ? "MEASURE" : "SEARCH";
  const sexcompat::Config defaults = sexcompat::Config::load(batchKeys(), "", {}, nullptr);
  std::vector<std::string> warnings;
  for (const std::string& key : keysOfTaskOnly(other)) {
    const std::string where = c.where(key);
    if (where.empty()) continue;
    const bool onCommandLine = where == sexcompat::kCommandLine;
    if (!onCommandLine && c.getStrings(key) == defaults.getStrings(key)) continue;
    warnings.push_back(where + ": " + (onCommandLine ? "-" : "") + key + " is not used with TASK " +
                       taskName + " (a key of TASK " + otherName + "; setting it has no effect)");
  }
  return warnings;
}

// TASK MEASURE: each tile is measured as `octarc measure` does it, on the settings of `run`.
void measureSettings(const sexcompat::Config& c, RunSettings run, BatchSettings& s) {
  if (!run.appendColumns && uppercase(run.catalogType) == "NONE") {
    throw ConfigError(
        "CATALOG_TYPE NONE: with TASK MEASURE and APPEND_COLUMNS N a batch writes each "
        "tile's catalog; give FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII or ASCII_VOTABLE");
  }
  s.outputDir = c.getString("OUTPUT_DIR");
  s.config = c;
  // What changes a tile's catalog: every key the measure run reads (not the search's), and
  // CATALOG_TYPE, the format of a new catalog.
  const std::vector<std::string> searchOnly = keysOfTaskOnly(BatchTask::Search);
  for (const ConfigurationItem& item : configurationValues(c, batchKeys())) {
    if (std::find(searchOnly.begin(), searchOnly.end(), item.key) == searchOnly.end()) {
      s.configuration.push_back(item);
    }
  }
  const std::string catalogType = c.getString("CATALOG_TYPE");
  s.configuration.push_back({"CATALOG_TYPE", catalogType, catalogType});
  s.configurationFiles.push_back({"PARAMETERS_NAME", run.parametersPath});
  s.tile.run = std::move(run);
}

}  // namespace

BatchSettings batchSettingsFromConfig(const sexcompat::Config& c, RunSettings run) {
  BatchSettings s;
  s.task = uppercase(c.getString("TASK")) == "MEASURE" ? BatchTask::Measure : BatchTask::Search;
  const bool measure = s.task == BatchTask::Measure;
  if (run.imagePaths.size() != 1) {
    throw ConfigError(measure ? "batch: give one manifest; see -h"
                              : "batch: give one manifest (or one quoted glob of images); see -h");
  }
  s.manifest = run.imagePaths.front();
  s.requestedThreads = run.threads;
  // A key a batch does not use: refused, except in the .sex file of the SExtractor runs that
  // a measuring batch reads, which names their files (WEIGHT_IMAGE weight.fits in SExtractor's
  // default.sex) and check-images: there it is said once and left. `why` follows "a batch".
  const auto notUsed = [&](const std::string& key, const std::string& why) {
    const std::string where = c.where(key);
    if (!measure || where == sexcompat::kCommandLine) {
      throw ConfigError(key + ": a batch " + why);
    }
    s.warnings.push_back(where + ": " + key + " is not used by a batch, which " + why);
  };
  std::vector<const char*> tileKeys = {"MASK_NAME", "INPUT_CATALOG", "WEIGHT_IMAGE"};
  if (measure) tileKeys.push_back("SEGMENTATION_NAME");
  for (const char* key : tileKeys) {
    if (c.where(key).empty()) continue;
    notUsed(key, std::string("takes each tile's files from the manifest ") +
                     (measure ? "(IMAGE SEGMENTATION CATALOG WEIGHT per line, TASK MEASURE)"
                              : "(IMAGE WEIGHT MASK CATALOG per line)"));
  }
  if (!measure && c.count("COLOUR_IMAGE") > 0) {
    throw ConfigError(
        "COLOUR_IMAGE: a batch's manifest holds one image per tile; search the "
        "tiles one by one (octarc search) to measure colours");
  }
  if (!measure && c.count("LENS_LIGHT_BAND") > 0) {
    throw ConfigError(
        "LENS_LIGHT_BAND: a batch's manifest holds one image per tile; search the tiles one "
        "by one (octarc search) to fit the lenses in another band");
  }
  if (c.isExplicit("CHECKIMAGE_TYPE") && uppercase(c.getString("CHECKIMAGE_TYPE")) != "NONE") {
    notUsed("CHECKIMAGE_TYPE", "writes no check-images");
  }
  for (std::string& w : otherTaskKeyWarnings(c, s.task)) s.warnings.push_back(std::move(w));
  s.restart = c.getBool("RESTART");
  if (measure) {
    measureSettings(c, std::move(run), s);
  } else {
    s.tile = searchSettingsFromConfig(c, std::move(run));
    s.outputDir = s.tile.outputDir;
    s.matchRadiusArcsec = c.getDouble("MATCH_RADIUS");
    s.configuration = configurationValues(c, batchKeys());
    // The files are those the search reads, as the run found them (PARAMETERS_NAME and
    // FILTER_NAME looked up in octarc's data folder too).
    s.configurationFiles.push_back({"PARAMETERS_NAME", s.tile.run.parametersPath});
    if (s.tile.run.filter) s.configurationFiles.push_back({"FILTER_NAME", s.tile.run.filterPath});
    if (uppercase(c.getString("SELECTION_METHOD")) == "TREES") {
      s.configurationFiles.push_back({"MODEL_NAME", s.tile.modelPath});
    } else {
      s.configurationFiles.push_back({"GRID_NAME", s.tile.gridPath});
    }
  }
  for (const ConfigurationItem& item : s.configuration) {
    if (!c.isExplicit(item.key)) s.keysAtDefault.push_back(item.key);
  }
  std::string share = uppercase(c.getString("ARRAY_TASK"));
  if (share == "AUTO") {
    const ArrayShare slurm =
        slurmArrayShare(std::getenv("SLURM_ARRAY_TASK_ID"), std::getenv("SLURM_ARRAY_TASK_MIN"),
                        std::getenv("SLURM_ARRAY_TASK_MAX"), std::getenv("SLURM_ARRAY_TASK_STEP"),
                        std::getenv("SLURM_ARRAY_TASK_COUNT"));
    s.arrayTask = slurm.task;
    s.arrayTasks = slurm.tasks;
    s.arrayShareNote = slurm.note;
    return s;
  }
  const std::size_t slash = share.find('/');
  try {
    std::size_t used = 0;
    if (slash == std::string::npos) throw std::invalid_argument(share);
    s.arrayTask = std::stoi(share.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument(share);
    s.arrayTasks = std::stoi(share.substr(slash + 1), &used);
    if (used != share.size() - slash - 1) throw std::invalid_argument(share);
  } catch (const std::exception&) {
    throw ConfigError("ARRAY_TASK " + quoteForMessage(share) + ": give I/N (0 <= I < N) or AUTO");
  }
  if (s.arrayTasks < 1 || s.arrayTask < 0 || s.arrayTask >= s.arrayTasks) {
    throw ConfigError("ARRAY_TASK " + share + ": give I/N with 0 <= I < N");
  }
  return s;
}

}  // namespace octarc
