// The configuration a survey's tiles are searched with, kept in OUTPUT_DIR/configuration.txt by
// the first run: a rerun (or a run sharing the directory) with another one would merge tiles of
// two searches, and is refused unless RESTART Y sets the earlier tiles aside.
//
//   # comment lines
//   KEY <tab> COMPARED <tab> VALUE
//
// VALUE is the key's value after the command line's overrides, as the messages show it;
// COMPARED is what must agree: the value itself, or for a file the search reads (PARAMETERS_NAME,
// FILTER_NAME, GRID_NAME, MODEL_NAME) a hash of its content, so that a copy elsewhere agrees and
// a file changed in place does not.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "octarc/sexcompat/Config.h"

namespace octarc {

struct ConfigurationItem {
  std::string key;
  std::string compared;
  std::string value;
};

// The keys that do not change a tile's search: how it runs (NTHREADS, VERBOSE_TYPE), which run
// does it (ARRAY_TASK, RESTART), where (OUTPUT_DIR), and what only the survey's merge uses
// (MATCH_RADIUS, CATALOG_TYPE: it is redone by the run that writes the survey), and the names
// of outputs a batch does not write (CATALOG_NAME, CHECKIMAGE_NAME).
bool keyLeavesTilesAlone(const std::string& key);

// Every key of `schema` that changes a tile's search (not keyLeavesTilesAlone, nor ignored by
// octarc), with its value; comma lists joined by ", ".
std::vector<ConfigurationItem> configurationValues(const sexcompat::Config& config,
                                                   const std::vector<sexcompat::KeySpec>& schema);

// The item of a file the search reads: `path` as value, the FNV-1a 64-bit hash of its content
// ("content 0123456789abcdef") compared; "no file" when it cannot be read.
ConfigurationItem fileItem(const std::string& key, const std::string& path);

std::string formatConfiguration(const std::vector<ConfigurationItem>& items);
// ConfigError naming `path` and the line for a line that is not KEY, COMPARED and VALUE.
std::vector<ConfigurationItem> parseConfiguration(const std::string& text, const std::string& path);

// "KEY RECORDED, this run has CURRENT" for every key whose compared parts differ (or that one of
// them lacks: "none"), in the order of `recorded`, then the keys only `current` has.
std::vector<std::string> configurationDifferences(const std::vector<ConfigurationItem>& recorded,
                                                  const std::vector<ConfigurationItem>& current);

}  // namespace octarc
