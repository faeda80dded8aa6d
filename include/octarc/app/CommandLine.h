// Command-line handling shared by the octarc commands: SExtractor-style `-c file` and
// `-KEY value` overrides, `-d`/`-dd`/`-dp` dumps, `-h` and `-v`.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/AtomicFile.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The octarc version string, e.g. "0.1.0".
const char* octarcVersion();

// A command's configuration: the defaults of its key table, then the -c file (or ./default.sex),
// then the -KEY value overrides; its positional arguments; warnings not yet printed.
struct LoadedConfig {
  sexcompat::Config config;
  std::vector<std::string> positional;
  std::string configFile;
  std::vector<std::string> warnings;
};

// Parses `octarc <command>` arguments against `schema`: nullopt when they only asked for help, a
// version, a dump of the keys (-d, -dd) or of the columns (-dp, with printColumnList; without it
// -dp dumps the keys), all printed on stdout. `readDefaultSex`: without -c, ./default.sex is read
// when it exists, as SExtractor does. `argumentName` names a positional argument in messages.
std::optional<LoadedConfig> loadConfig(const std::vector<std::string>& args,
                                       const std::string& command,
                                       const std::vector<sexcompat::KeySpec>& schema,
                                       const std::function<void()>& printUsage,
                                       const std::function<void()>& printColumnList,
                                       bool readDefaultSex,
                                       const std::string& argumentName = "image name");

struct LoadedRun {
  sexcompat::Config config;
  RunSettings settings;
  std::vector<std::string> warnings;  // the configuration's warnings (printed unless QUIET)
};

// "octarc <command> <args...>", as the XML run summary records it.
std::string commandLineText(const std::string& command, const std::vector<std::string>& args);

// WRITE_XML for a detect or measure run: registers XML_NAME with `outputs` (after the run's
// other outputs), refusing it over any of `inputs`; returns its index, or -1 without WRITE_XML.
int addXmlOutput(const RunSettings& settings, OutputFiles& outputs,
                 const std::vector<NamedInput>& inputs);

// Parses the arguments of `octarc <command>`, loads the configuration and returns the run's
// settings, or nullopt when the arguments only asked for help, a version or a dump (already
// printed on stdout). Configuration warnings go to stderr unless VERBOSE_TYPE is QUIET.
std::optional<LoadedRun> loadRun(const std::vector<std::string>& args, const std::string& command,
                                 const std::function<void()>& printUsage);
// The same with another key table (detect's keys and a command's own) and -dp listing;
// `argumentName` names the positional arguments in messages, and `weightMapsElsewhere` lets
// WEIGHT_TYPE stand without WEIGHT_IMAGE (a batch's manifest gives the maps).
std::optional<LoadedRun> loadRun(const std::vector<std::string>& args, const std::string& command,
                                 const std::vector<sexcompat::KeySpec>& schema,
                                 const std::function<void()>& printUsage,
                                 const std::function<void()>& printColumnList,
                                 const std::string& argumentName = "image name",
                                 bool weightMapsElsewhere = false);

// The image(s) of a detect, search or measure run, from its arguments (setImagePaths): one
// image, or with `dualAllowed` SExtractor's dual-image syntax (DETECT,MEASURE or two names).
// ConfigError otherwise, naming the command.
void requireImages(RunSettings& settings, const std::string& command, bool dualAllowed);

}  // namespace octarc
