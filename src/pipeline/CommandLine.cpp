#include "octarc/pipeline/CommandLine.h"

#include <filesystem>
#include <iostream>

#include "octarc/core/Column.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Version.h"
#include "octarc/measure/Registry.h"
#include "octarc/sexcompat/Assoc.h"
#include "octarc/sexcompat/Keys.h"

namespace octarc {

namespace {

// `-dp`: every column, as a commented .param template (SExtractor's format).
void printColumns() {
  std::vector<ColumnSpec> columns = allBuiltinColumns();
  columns.push_back(sexcompat::vectorAssocColumn(1));
  columns.push_back(sexcompat::numberAssocColumn());
  for (const ColumnSpec& c : columns) {
    char line[256];
    std::snprintf(line, sizeof line, "#%-24s %-57s", c.name.c_str(), c.description.c_str());
    std::cout << line;
    if (!c.unit.empty()) std::cout << " [" << c.unit << "]";
    std::cout << "\n";
  }
}

}  // namespace

const char* octarcVersion() {
  return kVersion;
}

std::optional<LoadedRun> loadRun(const std::vector<std::string>& args, const std::string& command,
                                 const std::function<void()>& printUsage) {
  const std::vector<sexcompat::KeySpec> schema = sexcompat::octarcMeasureKeys();
  const sexcompat::CommandLine cl = sexcompat::parseCommandLine(args, schema);
  if (cl.help) {
    printUsage();
    return std::nullopt;
  }
  if (cl.version) {
    std::cout << "octarc " << command << " version " << octarcVersion() << "\n";
    return std::nullopt;
  }
  if (cl.dumpParams) {
    printColumns();
    return std::nullopt;
  }
  std::vector<std::string> warnings;
  if (cl.dumpConfig || cl.dumpConfigFull) {
    const sexcompat::Config defaults = sexcompat::Config::load(schema, "", {}, &warnings);
    std::cout << defaults.dump(schema, cl.dumpConfigFull);
    return std::nullopt;
  }
  // As SExtractor: without -c, ./default.sex is read when it exists.
  std::string configFile = cl.configFile;
  if (configFile.empty() && std::filesystem::exists("default.sex")) configFile = "default.sex";
  sexcompat::Config config = sexcompat::Config::load(schema, configFile, cl.overrides, &warnings);
  RunSettings settings = settingsFromConfig(config);
  for (const std::string& image : cl.positional) {
    // As for every configuration value: a control character is never part of a real name.
    if (hasControlCharacter(image)) {
      throw ConfigError("command line: image name " + quoteForMessage(image) +
                        " holds a control character");
    }
  }
  settings.imagePaths = cl.positional;
  settings.configPath = configFile;
  if (!settings.quiet) {
    for (const std::string& w : warnings) std::cerr << "WARNING: " << w << "\n";
  }
  return LoadedRun{std::move(config), std::move(settings)};
}

}  // namespace octarc
