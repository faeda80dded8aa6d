#include "octarc/pipeline/RunSettings.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

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
  const std::vector<sexcompat::KeySpec> schema = sexcompat::octarcMeasureKeys();
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

}  // namespace
}  // namespace octarc
