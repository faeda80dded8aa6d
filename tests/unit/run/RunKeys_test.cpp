// octarc's configuration keys (run/RunKeys.h): SExtractor's table with octarc's changes and keys.
#include "octarc/run/RunKeys.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/sexcompat/Keys.h"

namespace octarc {
namespace {

using sexcompat::Config;
using sexcompat::KeySpec;
using sexcompat::sextractorKeys;

TEST(OctarcKeys, ExtendsTheSextractorTable) {
  const std::vector<KeySpec> keys = octarcKeys();
  EXPECT_EQ(keys.size(), sextractorKeys().size() + 9);
  const Config c = Config::load(keys, "", {}, nullptr);
  EXPECT_EQ(c.count("SEGMENTATION_NAME"), 0);
  EXPECT_EQ(c.count("INPUT_CATALOG"), 0);
  EXPECT_EQ(c.count("BACKGROUND_NAME"), 0);
  EXPECT_EQ(c.count("BACKGROUND_RMS_NAME"), 0);
  EXPECT_DOUBLE_EQ(c.getDouble("DETECT_THRESH_MAX"), 20.0);
  // A configuration that asks for no levels behaves like SExtractor: one level.
  EXPECT_EQ(c.getInt("DETECT_NLEVELS"), 1);
  EXPECT_FALSE(c.getBool("REPLACE_INPUT_CATALOG"));
  EXPECT_EQ(c.count("DETECT_LEVELS"), 0);
  EXPECT_EQ(c.getInt("NTHREADS"), 0);
  EXPECT_TRUE(c.getBool("APPEND_COLUMNS"));
  EXPECT_EQ(c.getStrings("CATALOG_NAME"), (std::vector<std::string>{"test.cat"}));

  const Config d = Config::load(keys, "",
                                {{"SEGMENTATION_NAME", "seg1.fits,seg2.fits"},
                                 {"BACK_TYPE", "global"},
                                 {"DETECT_LEVELS", "2.5,5,10"},
                                 {"APPEND_COLUMNS", "n"},
                                 {"CATALOG_NAME", "a.ldac,b.ldac"}},
                                nullptr);
  EXPECT_FALSE(d.getBool("APPEND_COLUMNS"));
  EXPECT_EQ(d.getStrings("CATALOG_NAME"), (std::vector<std::string>{"a.ldac", "b.ldac"}));
  EXPECT_EQ(d.getStrings("SEGMENTATION_NAME"),
            (std::vector<std::string>{"seg1.fits", "seg2.fits"}));
  EXPECT_EQ(d.getString("BACK_TYPE"), "GLOBAL");
  EXPECT_EQ(d.getDoubles("DETECT_LEVELS"), (std::vector<double>{2.5, 5.0, 10.0}));
  EXPECT_THROW(Config::load(keys, "", {{"DETECT_NLEVELS", "0"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"DETECT_NLEVELS", "256"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"NTHREADS", "-1"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"BACKGROUND_NAME", "a.fits,b.fits"}}, nullptr),
               ConfigError);
}

TEST(OctarcKeys, FullDumpRoundTripsAndShortDumpHidesExpertKeys) {
  const std::vector<KeySpec> keys = octarcKeys();
  const Config c = Config::load(keys, "", {{"DETECT_LEVELS", "3,6"}}, nullptr);
  const auto dir = test::scratchDir();
  const std::string path = (dir / "octarc.sex").string();
  std::ofstream(path) << c.dump(keys, true);
  std::vector<std::string> warnings;
  const Config back = Config::load(keys, path, {}, &warnings);
  EXPECT_TRUE(warnings.empty());
  for (const auto& k : keys) EXPECT_EQ(back.getStrings(k.name), c.getStrings(k.name)) << k.name;
  const std::string shortDump = c.dump(keys, false);
  EXPECT_EQ(shortDump.find("ASSOC_RADIUS"), std::string::npos);
  EXPECT_NE(shortDump.find("DETECT_MINAREA"), std::string::npos);
}

}  // namespace
}  // namespace octarc
