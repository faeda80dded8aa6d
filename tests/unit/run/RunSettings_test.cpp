#include "octarc/run/RunSettings.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/RunKeys.h"
#include "octarc/sexcompat/Assoc.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/Keys.h"

namespace octarc {
namespace {

bool markedIgnored(const sexcompat::KeySpec& k) {
  return k.comment.find("(ignored by octarc)") != std::string::npos;
}

// `-dd` marks a key "(ignored by octarc)" exactly when no command reads it: every key that the
// settings of a detect/measure run (and its ASSOC settings) read is unmarked, and every unmarked
// key is read.
TEST(RunSettings, KeysMarkedIgnoredAreExactlyTheUnreadOnes) {
  const std::vector<sexcompat::KeySpec> schema = octarcKeys();
  // Options that switch on the reading of other keys (weight map, check images).
  const sexcompat::Config config = sexcompat::Config::load(schema, "",
                                                           {{"WEIGHT_TYPE", "MAP_WEIGHT"},
                                                            {"WEIGHT_IMAGE", "w.fits"},
                                                            {"WEIGHT_THRESH", "0"},
                                                            {"CHECKIMAGE_TYPE", "SEGMENTATION"},
                                                            {"DETECT_LEVELS", "2,4"},
                                                            {"BACKGROUND_NAME", "b.fits"},
                                                            {"BACKGROUND_RMS_NAME", "r.fits"},
                                                            {"SEGMENTATION_NAME", "s.fits"},
                                                            {"INPUT_CATALOG", "c.ldac"}},
                                                           nullptr);
  (void)settingsFromConfig(config);
  (void)sexcompat::AssocSettings::fromConfig(config);
  const std::set<std::string> read = config.keysRead();
  for (const sexcompat::KeySpec& k : schema) {
    if (read.count(k.name)) {
      EXPECT_FALSE(markedIgnored(k)) << k.name << " is used but marked ignored";
    } else {
      EXPECT_TRUE(markedIgnored(k)) << k.name << " is never read but not marked ignored";
    }
  }
  for (const char* used : {"WEIGHT_TYPE", "WEIGHT_IMAGE", "WEIGHT_THRESH", "RESCALE_WEIGHTS"}) {
    EXPECT_TRUE(read.count(used)) << used;
  }
}

TEST(RunSettings, InputsListEveryFileTheRunReads) {
  RunSettings s;
  s.imagePaths = {"image.fits"};
  s.configPath = "run.sex";
  s.filter = false;
  s.weightImagePath = "w.fits";
  s.segmentationPaths = {"s1.fits", "s2.fits"};
  s.inputCatalogPaths = {"c1.ldac", "c2.ldac"};
  const std::vector<NamedInput> inputs = runInputs(s, "list.txt");
  std::set<std::string> paths;
  for (const NamedInput& in : inputs) paths.insert(in.path);
  EXPECT_EQ(paths, (std::set<std::string>{"image.fits", "run.sex", "default.param", "w.fits",
                                          "s1.fits", "s2.fits", "c1.ldac", "c2.ldac", "list.txt"}));
}

RunSettings settingsFromFile(const std::string& text) {
  const std::filesystem::path path = test::scratchDir() / "run.sex";
  std::ofstream(path) << text;
  const sexcompat::Config config =
      sexcompat::Config::load(octarcKeys(), path.string(), {}, nullptr);
  return settingsFromConfig(config);
}

// Found by mutation fuzzing of .sex files: these lines ended in vector::_M_range_check, an
// internal error with exit status 3. A list given empty is "not given", as in SExtractor.
TEST(RunSettings, KeysGivenWithoutValueAreNotGiven) {
  const RunSettings s = settingsFromFile(
      "WEIGHT_TYPE\n"
      "WEIGHT_IMAGE\n"
      "WEIGHT_THRESH ,\n"
      "CHECKIMAGE_TYPE\n"
      "CHECKIMAGE_NAME ,\n"
      "SEGMENTATION_NAME\n"
      "INPUT_CATALOG\n"
      "BACKGROUND_NAME\n"
      "BACKGROUND_RMS_NAME ;\n"
      "DETECT_LEVELS\n"
      "FLAG_IMAGE\n"
      "FLAG_TYPE\n"
      "FILTER_THRESH\n");
  EXPECT_EQ(s.weightType, WeightType::None);
  EXPECT_FALSE(s.weightThreshold.has_value());
  EXPECT_TRUE(s.checkImageTypes.empty());
  EXPECT_TRUE(s.segmentationPaths.empty());
  EXPECT_TRUE(s.inputCatalogPaths.empty());
  EXPECT_TRUE(s.backgroundMapPath.empty());
  EXPECT_TRUE(s.backgroundRmsMapPath.empty());
  EXPECT_TRUE(s.detectLevels.empty());
}

TEST(RunSettings, WeightTypeWithABareWeightImageAsksForTheMap) {
  try {
    settingsFromFile("WEIGHT_TYPE MAP_WEIGHT\nWEIGHT_IMAGE\n");
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "WEIGHT_IMAGE: WEIGHT_TYPE MAP_WEIGHT needs a weight map file");
  }
}

TEST(RunSettings, PairsTakeTheSecondValueWhenGiven) {
  const RunSettings one = settingsFromFile("THRESH_TYPE ABSOLUTE\nBACK_SIZE 32\n");
  EXPECT_EQ(one.detectThresholdType, ThresholdType::Absolute);
  EXPECT_EQ(one.analysisThresholdType, ThresholdType::Absolute);
  EXPECT_EQ(one.backMeshWidthPix, 32);
  EXPECT_EQ(one.backMeshHeightPix, 32);
  const RunSettings two =
      settingsFromFile("THRESH_TYPE ABSOLUTE,RELATIVE\nBACK_SIZE 32,48\nBACK_FILTERSIZE 3,5\n");
  EXPECT_EQ(two.detectThresholdType, ThresholdType::Absolute);
  EXPECT_EQ(two.analysisThresholdType, ThresholdType::Relative);
  EXPECT_EQ(two.backMeshWidthPix, 32);
  EXPECT_EQ(two.backMeshHeightPix, 48);
  EXPECT_EQ(two.backFilterWidth, 3);
  EXPECT_EQ(two.backFilterHeight, 5);
}

// Every catalog row holds the whole VECTOR_ASSOC: a size from a .param file could ask for
// gigabytes per object. It is limited to the longest ASSOC_DATA list.
TEST(ColumnPlan, VectorAssocSizeIsLimited) {
  const std::filesystem::path dir = test::scratchDir();
  RunSettings s;
  s.parametersPath = (dir / "a.param").string();
  std::ofstream(s.parametersPath) << "NUMBER\nVECTOR_ASSOC(2048)\n";
  EXPECT_EQ(planColumns(s, true).assocVectorSize, 2048);
  std::ofstream(s.parametersPath) << "NUMBER\nVECTOR_ASSOC(64,64)\n";
  try {
    planColumns(s, true);
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              s.parametersPath +
                  ":2: VECTOR_ASSOC(4096): at most 2048 elements (the longest "
                  "ASSOC_DATA)");
  }
}

}  // namespace
}  // namespace octarc
