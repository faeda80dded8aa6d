#include "octarc/batch/BatchConfiguration.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "ExpectError.h"
#include "TestFiles.h"
#include "TestPaths.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;
using Kind = sexcompat::KeySpec::Kind;

sexcompat::KeySpec key(const char* name, std::vector<std::string> defaults, int maxCount = 1) {
  sexcompat::KeySpec k;
  k.name = name;
  k.kind = Kind::String;
  k.defaults = std::move(defaults);
  k.maxCount = maxCount;
  return k;
}

TEST(BatchConfiguration, TheValuesAreThoseOfTheKeysThatChangeATilesSearch) {
  std::vector<sexcompat::KeySpec> schema = {
      key("DETECT_THRESH", {"2.5"}), key("NTHREADS", {"0"}), key("OUTPUT_DIR", {"survey"}),
      key("XML_NAME", {"a.xml"}), key("SEARCH_SPACE", {"a", "b"}, 4)};
  schema[3].ignored = true;
  const sexcompat::Config config = sexcompat::Config::load(
      schema, "", {{"DETECT_THRESH", "3.0"}, {"NTHREADS", "4"}, {"OUTPUT_DIR", "x"}}, nullptr);
  const std::vector<ConfigurationItem> items = configurationValues(config, schema);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].key, "DETECT_THRESH");
  EXPECT_EQ(items[0].value, "3.0");
  EXPECT_EQ(items[0].compared, "3.0");
  EXPECT_EQ(items[1].key, "SEARCH_SPACE");
  EXPECT_EQ(items[1].value, "a, b");
  for (const char* k : {"NTHREADS", "VERBOSE_TYPE", "ARRAY_TASK", "RESTART", "OUTPUT_DIR",
                        "MATCH_RADIUS", "CATALOG_TYPE", "CATALOG_NAME", "CHECKIMAGE_NAME"}) {
    EXPECT_TRUE(keyLeavesTilesAlone(k)) << k;
  }
  for (const char* k : {"DETECT_THRESH", "GRID_NAME", "WEIGHT_TYPE", "STAMPS"}) {
    EXPECT_FALSE(keyLeavesTilesAlone(k)) << k;
  }
}

TEST(BatchConfiguration, AFileIsComparedByTheFnv1aHashOfItsContent) {
  const fs::path dir = test::scratchDir();
  // The published FNV-1a 64-bit values of "" and "a".
  EXPECT_EQ(fileItem("GRID_NAME", test::writeTextFile(dir / "empty.grid", "")).compared,
            "content cbf29ce484222325");
  const ConfigurationItem a = fileItem("GRID_NAME", test::writeTextFile(dir / "a.grid", "a"));
  EXPECT_EQ(a.compared, "content af63dc4c8601ec8c");
  EXPECT_EQ(a.value, (dir / "a.grid").string());
  EXPECT_EQ(fileItem("MODEL_NAME", (dir / "absent").string()).compared, "no file");
}

TEST(BatchConfiguration, TheFileReadsBackAndABadLineIsNamed) {
  const std::vector<ConfigurationItem> items = {
      {"DETECT_THRESH", "2.5", "2.5"}, {"GRID_NAME", "content 00ff", "a b.grid"}, {"X", "", ""}};
  const std::vector<ConfigurationItem> back =
      parseConfiguration(formatConfiguration(items), "c.txt");
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].key, items[i].key);
    EXPECT_EQ(back[i].compared, items[i].compared);
    EXPECT_EQ(back[i].value, items[i].value);
  }
  test::expectError<ConfigError>(
      [] { parseConfiguration("# c\nDETECT_THRESH 2.5\n", "out/configuration.txt"); },
      {"out/configuration.txt:2: ", "not KEY <tab> COMPARED <tab> VALUE"});
}

TEST(BatchConfiguration, TheDifferencesNameEachKeyWithBothValues) {
  const std::vector<ConfigurationItem> recorded = {{"DETECT_THRESH", "2.5", "2.5"},
                                                   {"GRID_NAME", "content 01", "a/x.grid"},
                                                   {"MODEL_NAME", "content 02", "m.fits"},
                                                   {"SNR_MIN", "5", "5"},
                                                   {"NAME_PREFIX", "", ""}};
  const std::vector<ConfigurationItem> current = {{"DETECT_THRESH", "3.0", "3.0"},
                                                  {"GRID_NAME", "content 01", "b/x.grid"},
                                                  {"MODEL_NAME", "content 03", "m.fits"},
                                                  {"NAME_PREFIX", "des", "des"},
                                                  {"LENS_LIGHT", "Y", "Y"}};
  // GRID_NAME: a copy elsewhere of the same file agrees.
  const std::vector<std::string> expected = {
      "DETECT_THRESH 2.5, this run has 3.0",
      "MODEL_NAME m.fits (content 02), this run has m.fits (content 03)",
      "SNR_MIN 5, this run has none", "NAME_PREFIX (empty), this run has des",
      "LENS_LIGHT none, this run has Y"};
  EXPECT_EQ(configurationDifferences(recorded, current), expected);
  EXPECT_TRUE(configurationDifferences(current, current).empty());
}

}  // namespace
}  // namespace octarc
