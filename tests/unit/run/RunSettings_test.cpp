#include "octarc/run/RunSettings.h"

#include <gtest/gtest.h>

#include <cstdio>
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

// Dual-image mode: the second value of BACK_TYPE, BACK_VALUE, WEIGHT_TYPE, WEIGHT_IMAGE and
// WEIGHT_THRESH is the measurement image's, the first value when only one is given.
TEST(RunSettings, MeasurementImageTakesTheSecondValues) {
  const RunSettings two = settingsFromFile(
      "BACK_TYPE MANUAL,AUTO\nBACK_VALUE 10,20\nWEIGHT_TYPE MAP_RMS,MAP_WEIGHT\n"
      "WEIGHT_IMAGE d.fits,m.fits\nWEIGHT_THRESH 100,0.5\nFILTER Y\n");
  EXPECT_EQ(two.backgroundType, BackgroundType::Manual);
  EXPECT_EQ(two.backgroundValueAdu, 10.0);
  EXPECT_EQ(two.weightType, WeightType::MapRms);
  EXPECT_EQ(two.weightImagePath, "d.fits");
  EXPECT_EQ(two.weightThreshold, 100.0);
  const RunSettings measured = measurementImageSettings(two);
  EXPECT_EQ(measured.backgroundType, BackgroundType::Auto);
  EXPECT_EQ(measured.backgroundValueAdu, 20.0);
  EXPECT_EQ(measured.weightType, WeightType::MapWeight);
  EXPECT_EQ(measured.weightImagePath, "m.fits");
  EXPECT_EQ(measured.weightThreshold, 0.5);
  EXPECT_FALSE(measured.filter);  // the filter belongs to detection
  EXPECT_TRUE(two.filter);

  const RunSettings one = settingsFromFile("WEIGHT_TYPE MAP_VAR\nWEIGHT_IMAGE w.fits\n");
  EXPECT_EQ(one.measurement.weightType, WeightType::MapVariance);
  EXPECT_EQ(one.measurement.weightImagePath, "w.fits");
  // Weights for the measurement image alone.
  const RunSettings second = settingsFromFile("WEIGHT_TYPE NONE,MAP_WEIGHT\nWEIGHT_IMAGE m.fits\n");
  EXPECT_EQ(second.weightType, WeightType::None);
  EXPECT_TRUE(second.weightImagePath.empty());
  EXPECT_EQ(second.measurement.weightImagePath, "m.fits");
}

TEST(RunSettings, ImageArgumentsInSExtractorsSyntax) {
  RunSettings s;
  setImagePaths(s, {"det.fits,meas.fits"});
  EXPECT_TRUE(s.dualImage());
  EXPECT_EQ(s.detectionImagePath(), "det.fits");
  EXPECT_EQ(s.measurementImagePath(), "meas.fits");
  setImagePaths(s, {"det.fits", "meas.fits"});
  EXPECT_EQ(s.imagePaths, (std::vector<std::string>{"det.fits", "meas.fits"}));
  setImagePaths(s, {"one.fits"});
  EXPECT_FALSE(s.dualImage());
  EXPECT_EQ(s.detectionImagePath(), "one.fits");
  EXPECT_EQ(s.measurementImagePath(), "one.fits");
  // A file whose name holds a comma is that file.
  const std::string comma = testing::TempDir() + "a,b.fits";
  std::ofstream(comma) << "x";
  setImagePaths(s, {comma});
  EXPECT_EQ(s.imagePaths, std::vector<std::string>{comma});
  std::remove(comma.c_str());
  EXPECT_THROW(setImagePaths(s, {}), ConfigError);
  EXPECT_THROW(setImagePaths(s, {"a", "b", "c"}), ConfigError);
  EXPECT_THROW(setImagePaths(s, {"a,b,c"}), ConfigError);
  EXPECT_THROW(setImagePaths(s, {"a,b", "c"}), ConfigError);
  EXPECT_THROW(setImagePaths(s, {",b"}), ConfigError);
  s.backgroundMapPath = "back.fits";
  try {
    setImagePaths(s, {"a,b"});
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "BACKGROUND_NAME: background maps are for one image, not for a dual-image run");
  }
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
