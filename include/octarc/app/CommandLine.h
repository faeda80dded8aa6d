// Command-line handling shared by the octarc commands: SExtractor-style `-c file` and
// `-KEY value` overrides, `-d`/`-dd`/`-dp` dumps, `-h` and `-v`.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The octarc version string, e.g. "0.1.0".
const char* octarcVersion();

struct LoadedRun {
  sexcompat::Config config;
  RunSettings settings;
};

// Parses the arguments of `octarc <command>`, loads the configuration and returns the run's
// settings, or nullopt when the arguments only asked for help, a version or a dump (already
// printed on stdout). Configuration warnings go to stderr unless VERBOSE_TYPE is QUIET.
std::optional<LoadedRun> loadRun(const std::vector<std::string>& args, const std::string& command,
                                 const std::function<void()>& printUsage);

// The single image of a detect/measure run (settings.imagePaths[0]). ConfigError when none or
// several are given; SExtractor's dual-image syntax (IMAGE_DETECT,IMAGE_MEASURE or two images)
// is named as such: it is not supported yet.
const std::string& requireSingleImage(const RunSettings& settings, const std::string& command);

}  // namespace octarc
