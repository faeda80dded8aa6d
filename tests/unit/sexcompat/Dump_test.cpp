// The -d / -dd dumps of octarc's key table (what `octarc measure|detect -d/-dd` print): every
// key once, in table order, and a dump read back as a .sex file gives the same values, the
// defaults as well as values set by a file and the command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "TestPaths.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/Keys.h"

namespace octarc::sexcompat {
namespace {

// The key of every line of a dump that is not a comment, in order.
std::vector<std::string> dumpedKeys(const std::string& text) {
  std::vector<std::string> keys;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t start = line.find_first_not_of(' ');
    if (start == std::string::npos || line[start] == '#') continue;
    keys.push_back(line.substr(start, line.find(' ', start) - start));
  }
  return keys;
}

Config reload(const std::string& text, const std::vector<KeySpec>& schema) {
  const auto file = test::scratchDir() / "dump.sex";
  std::ofstream(file) << text;
  std::vector<std::string> warnings;
  Config c = Config::load(schema, file.string(), {}, &warnings);
  // Keys octarc ignores set to another value than their default are said to have no effect;
  // nothing else is warned of.
  for (const std::string& w : warnings) {
    EXPECT_NE(w.find("is ignored by octarc (setting it has no effect)"), std::string::npos) << w;
  }
  return c;
}

void expectSameValues(const Config& a, const Config& b, const std::vector<KeySpec>& schema) {
  for (const KeySpec& k : schema) {
    EXPECT_EQ(a.getStrings(k.name), b.getStrings(k.name)) << k.name;
  }
}

TEST(ConfigDump, FullDumpListsEveryKeyOnceInTableOrder) {
  const std::vector<KeySpec> schema = sextractorKeys();
  const Config defaults = Config::load(schema, "", {}, nullptr);
  std::vector<std::string> names;
  for (const KeySpec& k : schema) names.push_back(k.name);
  EXPECT_EQ(dumpedKeys(defaults.dump(schema, true)), names);
}

TEST(ConfigDump, ShortDumpListsTheKeysThatAreNotForExperts) {
  const std::vector<KeySpec> schema = sextractorKeys();
  const Config defaults = Config::load(schema, "", {}, nullptr);
  std::vector<std::string> names;
  for (const KeySpec& k : schema)
    if (!k.expertOnly) names.push_back(k.name);
  ASSERT_LT(names.size(), schema.size());
  EXPECT_EQ(dumpedKeys(defaults.dump(schema, false)), names);
}

TEST(ConfigDump, DefaultsLoadBack) {
  const std::vector<KeySpec> schema = sextractorKeys();
  const Config defaults = Config::load(schema, "", {}, nullptr);
  for (const bool full : {false, true}) {
    expectSameValues(reload(defaults.dump(schema, full), schema), defaults, schema);
  }
}

// A value of each key that differs from its default and is valid for it: the other boolean,
// another keyword, a number inside the range, two elements where a list may have two.
std::string otherValue(const KeySpec& k) {
  const std::string first = k.defaults.empty() ? "" : k.defaults.front();
  std::string one;
  switch (k.kind) {
    case KeySpec::Kind::Bool:
      one = first == "Y" ? "N" : "Y";
      break;
    case KeySpec::Kind::Keyword:
      one =
          k.keywords.front() == first && k.keywords.size() > 1 ? k.keywords[1] : k.keywords.front();
      break;
    case KeySpec::Kind::Int:
    case KeySpec::Kind::Float: {
      const double wanted = k.kind == KeySpec::Kind::Int ? 3.0 : 2.75;
      const double v = std::min(std::max(wanted, k.minValue), k.maxValue);
      std::ostringstream s;
      s << (k.kind == KeySpec::Kind::Int ? double(int(v)) : v);
      one = s.str();
      break;
    }
    case KeySpec::Kind::String:
      one = "other_" + k.name + ".txt";
      break;
  }
  return k.maxCount >= 2 ? one + "," + one : one;
}

TEST(ConfigDump, ValuesFromFileAndCommandLineLoadBack) {
  const std::vector<KeySpec> schema = sextractorKeys();
  std::vector<std::pair<std::string, std::string>> overrides;
  for (const KeySpec& k : schema) overrides.emplace_back(k.name, otherValue(k));
  // Half of the keys from a file, the other half from the command line.
  const auto file = test::scratchDir() / "set.sex";
  {
    std::ofstream out(file);
    for (std::size_t i = 0; i < overrides.size(); i += 2)
      out << overrides[i].first << "  " << overrides[i].second << "\n";
  }
  std::vector<std::pair<std::string, std::string>> commandLine;
  for (std::size_t i = 1; i < overrides.size(); i += 2) commandLine.push_back(overrides[i]);
  const Config set = Config::load(schema, file.string(), commandLine, nullptr);
  const Config defaults = Config::load(schema, "", {}, nullptr);
  int changed = 0;
  for (const KeySpec& k : schema) changed += set.getStrings(k.name) != defaults.getStrings(k.name);
  EXPECT_GT(changed, int(schema.size()) * 9 / 10);  // the round trip below carries information
  expectSameValues(reload(set.dump(schema, true), schema), set, schema);
}

}  // namespace
}  // namespace octarc::sexcompat
