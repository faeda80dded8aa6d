#include "octarc/batch/BatchConfiguration.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

std::string hashText(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

// "VALUE", and " (COMPARED)" when that is not the value itself (a file's content).
std::string shown(const ConfigurationItem& item) {
  const std::string value = item.value.empty() ? "(empty)" : item.value;
  return item.compared == item.value ? value : value + " (" + item.compared + ")";
}

}  // namespace

bool keyLeavesTilesAlone(const std::string& key) {
  static const std::set<std::string> keys = {"NTHREADS",     "VERBOSE_TYPE", "ARRAY_TASK",
                                             "RESTART",      "OUTPUT_DIR",   "MATCH_RADIUS",
                                             "CATALOG_TYPE", "CATALOG_NAME", "CHECKIMAGE_NAME"};
  return keys.count(key) > 0;
}

std::vector<ConfigurationItem> configurationValues(const sexcompat::Config& config,
                                                   const std::vector<sexcompat::KeySpec>& schema) {
  std::vector<ConfigurationItem> items;
  for (const sexcompat::KeySpec& k : schema) {
    if (k.ignored || keyLeavesTilesAlone(k.name)) continue;
    std::string value;
    for (const std::string& v : config.getStrings(k.name)) {
      value += (value.empty() ? "" : ", ") + v;
    }
    items.push_back({k.name, value, value});
  }
  return items;
}

ConfigurationItem fileItem(const std::string& key, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {key, "no file", path};
  // FNV-1a: a few lines, and fast enough for the grids and models (megabytes) once per run.
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      hash = (hash ^ static_cast<unsigned char>(buffer[i])) * 0x100000001b3ULL;
    }
  }
  if (in.bad()) return {key, "no file", path};
  return {key, "content " + hashText(hash), path};
}

std::string formatConfiguration(const std::vector<ConfigurationItem>& items) {
  std::string text =
      "# The configuration this OUTPUT_DIR's tiles are searched with (octarc batch): KEY, what\n"
      "# must agree (the value, or a file's content hash), the value. A run with another one\n"
      "# is refused; RESTART Y sets the earlier tiles aside and starts over.\n";
  for (const ConfigurationItem& i : items) {
    text += i.key + "\t" + i.compared + "\t" + i.value + "\n";
  }
  return text;
}

std::vector<ConfigurationItem> parseConfiguration(const std::string& text,
                                                  const std::string& path) {
  std::vector<ConfigurationItem> items;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t a = line.find('\t');
    const std::size_t b = a == std::string::npos ? a : line.find('\t', a + 1);
    if (b == std::string::npos || a == 0) {
      throw ConfigError(path + ":" + std::to_string(n) +
                        ": not KEY <tab> COMPARED <tab> VALUE (an octarc batch's configuration "
                        "file, changed by hand?)");
    }
    items.push_back({line.substr(0, a), line.substr(a + 1, b - a - 1), line.substr(b + 1)});
  }
  return items;
}

std::vector<std::string> configurationDifferences(const std::vector<ConfigurationItem>& recorded,
                                                  const std::vector<ConfigurationItem>& current) {
  std::map<std::string, const ConfigurationItem*> now;
  for (const ConfigurationItem& i : current) now[i.key] = &i;
  std::vector<std::string> differences;
  std::set<std::string> seen;
  for (const ConfigurationItem& was : recorded) {
    seen.insert(was.key);
    const auto it = now.find(was.key);
    if (it == now.end()) {
      differences.push_back(was.key + " " + shown(was) + ", this run has none");
    } else if (it->second->compared != was.compared) {
      differences.push_back(was.key + " " + shown(was) + ", this run has " + shown(*it->second));
    }
  }
  for (const ConfigurationItem& i : current) {
    if (!seen.count(i.key)) differences.push_back(i.key + " none, this run has " + shown(i));
  }
  return differences;
}

}  // namespace octarc
