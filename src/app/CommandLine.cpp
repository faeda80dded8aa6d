#include "octarc/app/CommandLine.h"

#include <filesystem>
#include <iostream>

#include "octarc/core/Column.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Version.h"
#include "octarc/measure/Registry.h"
#include "octarc/run/RunKeys.h"
#include "octarc/search/CandidateTable.h"
#include "octarc/selection/ColumnExpression.h"
#include "octarc/sexcompat/Assoc.h"

namespace octarc {

namespace {

// PARAMETERS_NAME as a path to read. Not given (or SExtractor's default.param, as a -d template
// writes it), and no default.param here or shipped: the shipped column list, with a warning. Given:
// as FILTER_NAME, a name without a directory that is not in the working directory may be a shipped
// file (so that `-c share/octarc/octarc.sex` works from anywhere); a file found nowhere is an error
// naming it.
std::string resolveParametersFile(const std::string& path, bool given,
                                  std::vector<std::string>& warnings) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // SExtractor's default name, as a template (-d) writes it, counts as not given.
  if ((!given || path == "default.param") && !fs::exists(userOrDataFile(path), ec)) {
    std::string shipped;
    try {
      shipped = dataFile("octarc.param");
    } catch (const IoError& e) {
      throw IoError(
          path +
          ": not found (PARAMETERS_NAME not given), nor the shipped column list: " + e.what());
    }
    warnings.push_back(path + " not found, using the shipped column list " + shipped);
    return shipped;
  }
  return existingUserOrDataFile(path, "PARAMETERS_NAME file");
}

}  // namespace

void requireImages(RunSettings& s, const std::string& command, bool dualAllowed) {
  if (s.imagePaths.empty() || s.imagePaths.size() > 2) {
    throw ConfigError(
        "octarc " + command + " takes " +
        (dualAllowed ? "one image, or a detection and a measurement image" : "exactly one image") +
        " (got " + std::to_string(s.imagePaths.size()) + "); see octarc " + command + " -h");
  }
  try {
    setImagePaths(s, s.imagePaths);
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + "; see octarc " + command + " -h");
  }
  if (s.dualImage() && !dualAllowed) {
    throw ConfigError("dual-image mode (" + s.detectionImagePath() + "," +
                      s.measurementImagePath() + ": detect on one image, measure on another) is " +
                      "for octarc detect and octarc search; octarc " + command +
                      " takes one image (see octarc " + command + " -h)");
  }
}

const char* octarcVersion() {
  return kVersion;
}

void printColumnList(const std::vector<ColumnSpec>& columns) {
  for (const ColumnSpec& c : columns) {
    char line[256];
    std::snprintf(line, sizeof line, "#%-24s %-57s", c.name.c_str(), c.description.c_str());
    std::cout << line;
    if (!c.unit.empty()) std::cout << " [" << c.unit << "]";
    std::cout << "\n";
  }
}

void printMeasuredColumns() {
  std::vector<ColumnSpec> columns = allBuiltinColumns();
  columns.push_back(sexcompat::vectorAssocColumn(1));
  columns.push_back(sexcompat::numberAssocColumn());
  printColumnList(columns);
}

void printCandidateColumns() {
  std::vector<ColumnSpec> columns;
  // The colour columns as they are named for a band B (one set per COLOUR_BAND).
  for (const CandidateColumnSpec& c : candidateColumns({"B"})) columns.push_back(c.spec);
  printColumnList(columns);
}

std::optional<sexcompat::CommandLine> parseArguments(const std::vector<std::string>& args,
                                                     const CommandSpec& command,
                                                     const std::vector<sexcompat::KeySpec>& keys) {
  sexcompat::CommandLine cl = sexcompat::parseCommandLine(args, keys);
  if (cl.help) {
    command.printUsage();
    return std::nullopt;
  }
  if (cl.version) {
    std::cout << "octarc " << command.name << " version " << octarcVersion() << "\n";
    return std::nullopt;
  }
  if (cl.dumpParams) {
    if (!command.printColumns) {
      throw ConfigError("-dp: octarc " + command.name +
                        " writes no catalog whose columns a .param file chooses (-d lists its "
                        "keys; see octarc " +
                        command.name + " -h)");
    }
    command.printColumns();
    return std::nullopt;
  }
  if (cl.dumpConfig || cl.dumpConfigFull) {
    std::vector<std::string> warnings;
    const sexcompat::Config defaults = sexcompat::Config::load(keys, "", {}, &warnings);
    std::cout << defaults.dump(keys, cl.dumpConfigFull);
    return std::nullopt;
  }
  return cl;
}

std::optional<LoadedConfig> loadConfig(const std::vector<std::string>& args,
                                       const CommandSpec& command,
                                       const std::vector<sexcompat::KeySpec>& schema,
                                       bool readDefaultSex, const std::string& argumentName) {
  const std::optional<sexcompat::CommandLine> cl = parseArguments(args, command, schema);
  if (!cl) return std::nullopt;
  LoadedConfig out;
  // As SExtractor: without -c, ./default.sex is read when it exists, with its warning when not.
  // A -c name without a directory may also be a shipped file (-c octarc.sex).
  out.configFile = cl->configFile.empty()
                       ? std::string()
                       : existingUserOrDataFile(cl->configFile, "configuration file (-c)");
  if (out.configFile.empty() && readDefaultSex) {
    if (std::filesystem::exists("default.sex")) {
      out.configFile = "default.sex";
    } else {
      out.warnings.push_back("default.sex not found, using internal defaults");
    }
  }
  out.config = sexcompat::Config::load(schema, out.configFile, cl->overrides, &out.warnings);
  for (const std::string& name : cl->positional) {
    // As for every configuration value: a control character is never part of a real name.
    if (hasControlCharacter(name)) {
      throw ConfigError("command line: " + argumentName + " " + quoteForMessage(name) +
                        " holds a control character");
    }
  }
  out.positional = cl->positional;
  return out;
}

std::optional<LoadedRun> loadRun(const std::vector<std::string>& args, const CommandSpec& command,
                                 const std::vector<sexcompat::KeySpec>& schema,
                                 const std::string& argumentName, bool weightMapsElsewhere) {
  std::optional<LoadedConfig> loaded = loadConfig(args, command, schema, true, argumentName);
  if (!loaded) return std::nullopt;
  RunSettings settings = settingsFromConfig(loaded->config, weightMapsElsewhere);
  settings.imagePaths = loaded->positional;
  settings.configPath = loaded->configFile;
  settings.parametersPath = resolveParametersFile(
      settings.parametersPath, loaded->config.isExplicit("PARAMETERS_NAME"), loaded->warnings);
  if (!settings.quiet) {
    for (const std::string& w : loaded->warnings) std::cerr << "WARNING: " << w << "\n";
  } else {
    setExpressionWarnings({});
  }
  return LoadedRun{std::move(loaded->config), std::move(settings), std::move(loaded->warnings)};
}

std::string commandLineText(const std::string& command, const std::vector<std::string>& args) {
  std::string text = "octarc " + command;
  for (const std::string& a : args) text += " " + a;
  return text;
}

}  // namespace octarc
