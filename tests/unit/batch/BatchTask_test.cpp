// TASK MEASURE's settings: the keys of the search warn (as the keys octarc ignores do: on the
// command line always, in a file only at another value than the default), a tile's own files
// are the manifest's, and the configuration recorded is the keys a tile's measure run reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "ExpectError.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/batch/BatchKeys.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

BatchSettings measureBatch(const std::string& file,
                           std::vector<std::pair<std::string, std::string>> overrides) {
  overrides.insert(overrides.begin(), {"TASK", "MEASURE"});
  const sexcompat::Config config = sexcompat::Config::load(batchKeys(), file, overrides, nullptr);
  RunSettings run = settingsFromConfig(config, true);
  run.imagePaths = {"tiles.csv"};
  return batchSettingsFromConfig(config, run);
}

bool hasKey(const std::vector<ConfigurationItem>& items, const std::string& key) {
  return std::any_of(items.begin(), items.end(),
                     [&](const ConfigurationItem& i) { return i.key == key; });
}

TEST(BatchTask, EachTaskHasKeysOfItsOwn) {
  const std::vector<std::string> search = keysOfTaskOnly(BatchTask::Search);
  for (const char* key : {"GRID_NAME", "MATCH_RADIUS", "STAMPS", "SEARCH_SPACE"}) {
    EXPECT_NE(std::find(search.begin(), search.end(), key), search.end()) << key;
  }
  for (const char* key : {"OUTPUT_DIR", "TASK", "RESTART", "ARRAY_TASK", "DETECT_THRESH",
                          "PARAMETERS_NAME", "APPEND_COLUMNS", "NTHREADS"}) {
    EXPECT_EQ(std::find(search.begin(), search.end(), key), search.end()) << key;
  }
  EXPECT_EQ(keysOfTaskOnly(BatchTask::Measure), std::vector<std::string>{"APPEND_COLUMNS"});
}

TEST(BatchTask, MeasureSettingsWarningsAndConfiguration) {
  const fs::path dir = test::scratchDir();
  // A file at the defaults but one: only that one and the command line's warn.
  const std::string file = test::writeTextFile(dir / "b.sex",
                                               "GRID_NAME arcs.grid.fits\n"
                                               "SNR_MIN 20\n");
  const BatchSettings s =
      measureBatch(file, {{"MATCH_RADIUS", "2"}, {"OUTPUT_DIR", "out"}, {"APPEND_COLUMNS", "N"}});
  EXPECT_EQ(s.task, BatchTask::Measure);
  EXPECT_EQ(s.outputDir, "out");
  EXPECT_FALSE(s.tile.run.appendColumns);
  ASSERT_TRUE(s.config.has_value());
  const std::vector<std::string> expected = {
      file +
          ":2: SNR_MIN is not used with TASK MEASURE (a key of TASK SEARCH; setting it has "
          "no effect)",
      "command line: -MATCH_RADIUS is not used with TASK MEASURE (a key of TASK SEARCH; setting "
      "it has no effect)"};
  EXPECT_EQ(s.warnings, expected);
  // Recorded: what the measure run reads, and the format of its new catalogs; not the search's.
  EXPECT_TRUE(hasKey(s.configuration, "TASK"));
  EXPECT_TRUE(hasKey(s.configuration, "APPEND_COLUMNS"));
  EXPECT_TRUE(hasKey(s.configuration, "CATALOG_TYPE"));
  EXPECT_FALSE(hasKey(s.configuration, "GRID_NAME"));
  EXPECT_FALSE(hasKey(s.configuration, "MATCH_RADIUS"));
  ASSERT_EQ(s.configurationFiles.size(), 1u);
  EXPECT_EQ(s.configurationFiles[0].first, "PARAMETERS_NAME");
}

TEST(BatchTask, MeasureRefusesTileFilesAndNoCatalog) {
  test::expectError<ConfigError>(
      [] {
        measureBatch("", {{"SEGMENTATION_NAME", "a.fits"}});
      },
      {"SEGMENTATION_NAME", "IMAGE SEGMENTATION CATALOG WEIGHT"});
  test::expectError<ConfigError>(
      [] {
        measureBatch("", {{"INPUT_CATALOG", "a.ldac"}});
      },
      {"INPUT_CATALOG", "manifest"});
  test::expectError<ConfigError>(
      [] {
        measureBatch("", {{"APPEND_COLUMNS", "N"}, {"CATALOG_TYPE", "NONE"}});
      },
      {"CATALOG_TYPE NONE", "TASK MEASURE"});
}

}  // namespace
}  // namespace octarc
