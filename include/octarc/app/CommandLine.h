// Command-line handling shared by the octarc commands: SExtractor-style `-c file` and
// `-KEY value` overrides, `-d`/`-dd`/`-dp` dumps, `-h` and `-v`, parsed one way for every
// command (parseArguments; Options.h maps the simulations' long options onto it).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Column.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// The octarc version string, e.g. "0.1.0".
const char* octarcVersion();

// What the shared parse needs to know of a command.
struct CommandSpec {
  std::string name;                  // as typed after `octarc`: "detect", "simulate lenses"
  std::function<void()> printUsage;  // -h
  // -dp: the columns of the catalog the command writes, as a .param template; empty for a
  // command that writes no catalog (-dp is then an error).
  std::function<void()> printColumns;
};

// The one parse of every command's arguments, in SExtractor's style: `-KEY value` (the value is
// always the next argument, so negative numbers pass), `-c file`, positional arguments, and
// the flags -h (usage), -v (version), -d / -dd (the keys and their defaults as a .sex file, -dd
// with the expert keys) and -dp (the catalog's columns). A flag is acted on here, on stdout,
// and the result is then nullopt. ConfigError for an unknown key (with the nearest as a hint), a
// missing value, or -dp of a command that writes no catalog.
std::optional<sexcompat::CommandLine> parseArguments(const std::vector<std::string>& args,
                                                     const CommandSpec& command,
                                                     const std::vector<sexcompat::KeySpec>& keys);

// `-dp`'s listing: one commented line per column, "#NAME description [unit]" (SExtractor's
// .param layout).
void printColumnList(const std::vector<ColumnSpec>& columns);

// A command's configuration: the defaults of its key table, then the -c file (or ./default.sex),
// then the -KEY value overrides; its positional arguments; warnings not yet printed.
struct LoadedConfig {
  sexcompat::Config config;
  std::vector<std::string> positional;
  std::string configFile;
  std::vector<std::string> warnings;
};

// Parses `octarc <command>` arguments (parseArguments) against `schema` and loads the
// configuration: nullopt when they only asked for a flag. `readDefaultSex`: without -c,
// ./default.sex is read when it exists, as SExtractor does. `argumentName` names a positional
// argument in messages.
std::optional<LoadedConfig> loadConfig(const std::vector<std::string>& args,
                                       const CommandSpec& command,
                                       const std::vector<sexcompat::KeySpec>& schema,
                                       bool readDefaultSex,
                                       const std::string& argumentName = "image name");

struct LoadedRun {
  sexcompat::Config config;
  RunSettings settings;
  std::vector<std::string> warnings;  // the configuration's warnings (printed unless QUIET)
};

// "octarc <command> <args...>", as the XML run summary records it.
std::string commandLineText(const std::string& command, const std::vector<std::string>& args);

// Parses the arguments of `octarc <command>` (loadConfig with `schema`), loads the
// configuration and returns the run's settings, or nullopt when the arguments only asked for a
// flag. Configuration warnings go to stderr unless VERBOSE_TYPE is QUIET. `argumentName` names
// the positional arguments in messages, and `weightMapsElsewhere` lets WEIGHT_TYPE stand
// without WEIGHT_IMAGE (a batch's manifest gives the maps).
std::optional<LoadedRun> loadRun(const std::vector<std::string>& args, const CommandSpec& command,
                                 const std::vector<sexcompat::KeySpec>& schema,
                                 const std::string& argumentName = "image name",
                                 bool weightMapsElsewhere = false);

// `-dp` of detect and measure: every column octarc measures, and the ASSOC columns.
void printMeasuredColumns();
// `-dp` of search and demo: the columns of the candidate catalog, the colour columns as named
// for a band B.
void printCandidateColumns();

// The image(s) of a detect, search or measure run, from its arguments (setImagePaths): one
// image, or with `dualAllowed` SExtractor's dual-image syntax (DETECT,MEASURE or two names).
// ConfigError otherwise, naming the command.
void requireImages(RunSettings& settings, const std::string& command, bool dualAllowed);

}  // namespace octarc
