#include "octarc/sexcompat/Keys.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "TestCommands.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc::sexcompat {
namespace {

using test::commandOutput;
using test::haveSourceExtractor;

// Key names of a .sex text: the first token of every line that does not start with a blank or '#'.
std::vector<std::string> keyNames(const std::string& text) {
  std::vector<std::string> names;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == ' ' || line[0] == '#' || line[0] == '\t') continue;
    names.push_back(line.substr(0, line.find_first_of(" \t")));
  }
  return names;
}

std::vector<std::string> tableNames(bool full) {
  std::vector<std::string> names;
  for (const auto& k : sextractorKeys())
    if (full || !k.expertOnly) names.push_back(k.name);
  return names;
}

TEST(SextractorKeys, SameKeysInSameOrderAsSourceExtractorDumps) {
  if (!haveSourceExtractor()) OCTARC_SKIP_MISSING() << "source-extractor not installed";
  EXPECT_EQ(keyNames(commandOutput("source-extractor -dd 2>/dev/null")), tableNames(true));
  EXPECT_EQ(keyNames(commandOutput("source-extractor -d 2>/dev/null")), tableNames(false));
}

TEST(SextractorKeys, FullDumpOfSourceExtractorLoadsWithoutWarnings) {
  if (!haveSourceExtractor()) OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "default_full.sex",
                                               commandOutput("source-extractor -dd 2>/dev/null"));
  std::vector<std::string> warnings;
  const Config c = Config::load(sextractorKeys(), path, {}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  // Every key is set by the file, and the file's values equal the table's defaults; the two
  // keys the dump lists without a value (FILTER_THRESH, WEIGHT_THRESH) count as not given.
  const Config defaults = Config::load(sextractorKeys(), "", {}, nullptr);
  for (const auto& k : sextractorKeys()) {
    const bool bare = k.name == "FILTER_THRESH" || k.name == "WEIGHT_THRESH";
    EXPECT_EQ(c.isExplicit(k.name), !bare) << k.name;
    EXPECT_EQ(c.getStrings(k.name), defaults.getStrings(k.name)) << k.name;
  }
  EXPECT_EQ(c.getDoubles("PHOT_AUTOPARAMS"), (std::vector<double>{2.5, 3.5}));
  EXPECT_EQ(c.getInts("ASSOC_DATA"), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(c.count("FILTER_THRESH"), 0);
  EXPECT_EQ(c.getString("XSL_URL"), "file:///usr/share/source-extractor/source-extractor.xsl");
  EXPECT_EQ(c.getString("PATTERN_TYPE"), "RINGS-HARMONIC");
}

TEST(SextractorKeys, OurFullDumpIsReadBySourceExtractorWithoutComplaint) {
  if (!haveSourceExtractor()) OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const auto& keys = sextractorKeys();
  const Config c = Config::load(keys, "", {}, nullptr);
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "ours.sex", c.dump(keys, true));
  // source-extractor reads the configuration before it opens the (missing) image; it names every
  // unknown or out-of-range keyword it finds.
  const std::string log =
      commandOutput("cd " + dir.string() + " && source-extractor missing.fits -c ours.sex 2>&1");
  EXPECT_NE(log.find("Source Extractor"), std::string::npos) << log;
  EXPECT_EQ(log.find("keyword"), std::string::npos) << log;
  // And the check itself works: a wrong key is reported.
  test::writeTextFile(dir / "bad.sex", c.dump(keys, true) + "NO_SUCH_KEY 1\n");
  const std::string badLog =
      commandOutput("cd " + dir.string() + " && source-extractor missing.fits -c bad.sex 2>&1");
  EXPECT_NE(badLog.find("NO_SUCH_KEY keyword unknown"), std::string::npos) << badLog;
}

TEST(SextractorKeys, SharedNttEmmiConfigLoadsWithoutWarnings) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const auto path = shared / "ntt-emmi" / "default.sex";
  if (!std::filesystem::exists(path)) OCTARC_SKIP_MISSING() << path << " not found";
  std::vector<std::string> warnings;
  const Config c = Config::load(sextractorKeys(), path.string(), {}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(c.getString("CATALOG_TYPE"), "FITS_LDAC");
  EXPECT_EQ(c.getInt("DETECT_MINAREA"), 2);
  EXPECT_DOUBLE_EQ(c.getDouble("ANALYSIS_THRESH"), 2.0);
  EXPECT_EQ(c.getString("FILTER_NAME"), "gauss_4.0_7x7.conv");
  EXPECT_EQ(c.getString("WEIGHT_TYPE"), "NONE");
  EXPECT_TRUE(c.getBool("WRITE_XML"));
}

// Every key of a real configuration is known; the only warnings are for the keys octarc does not
// act on that it sets to another value than their default (its deblending, here).
TEST(SextractorKeys, SharedSepReferenceConfigLoadsWithoutUnknownKeys) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  const auto path = shared / "sep-reference" / "default.sex";
  if (!std::filesystem::exists(path)) OCTARC_SKIP_MISSING() << path << " not found";
  std::vector<std::string> warnings;
  Config::load(sextractorKeys(), path.string(), {}, &warnings);
  for (const std::string& w : warnings) {
    EXPECT_NE(w.find("is ignored by octarc (setting it has no effect)"), std::string::npos) << w;
  }
}

TEST(SextractorKeys, DebianDefaultSexLoadsWithoutWarnings) {
  const std::filesystem::path path = "/usr/share/source-extractor/default.sex";
  if (!std::filesystem::exists(path)) OCTARC_SKIP_MISSING() << path << " not found";
  std::vector<std::string> warnings;
  Config::load(sextractorKeys(), path.string(), {}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

TEST(SextractorKeys, RangesFromSextractorsKeyTable) {
  const auto& keys = sextractorKeys();
  EXPECT_THROW(Config::load(keys, "", {{"DEBLEND_NTHRESH", "65"}}, nullptr), ConfigError);
  EXPECT_NO_THROW(Config::load(keys, "", {{"DEBLEND_NTHRESH", "64"}}, nullptr));
  EXPECT_THROW(Config::load(keys, "", {{"DEBLEND_MINCONT", "1.01"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"MAG_ZEROPOINT", "100.5"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"ASSOC_PARAMS", "1"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"ASSOC_PARAMS", "0,2"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"BACK_TYPE", "GLOBAL"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"BACK_FILTERSIZE", "12"}}, nullptr), ConfigError);
  EXPECT_THROW(Config::load(keys, "", {{"PHOT_AUTOPARAMS", "2.5"}}, nullptr), ConfigError);
  const Config c = Config::load(keys, "", {{"CHECKIMAGE_TYPE", "segmentation,-objects"}}, nullptr);
  EXPECT_EQ(c.getStrings("CHECKIMAGE_TYPE"),
            (std::vector<std::string>{"SEGMENTATION", "-OBJECTS"}));
}

TEST(SextractorKeys, CommentsMarkIgnoredKeys) {
  int ignored = 0;
  for (const auto& k : sextractorKeys()) {
    EXPECT_FALSE(k.comment.empty()) << k.name;
    if (k.comment.find("(ignored by octarc)") != std::string::npos) ++ignored;
    if (k.name == "DEBLEND_NTHRESH" || k.name == "CLEAN" || k.name == "PHOT_APERTURES") {
      EXPECT_NE(k.comment.find("(ignored by octarc)"), std::string::npos) << k.name;
    }
    if (k.name == "DETECT_THRESH" || k.name == "ASSOC_TYPE" || k.name == "CATALOG_TYPE") {
      EXPECT_EQ(k.comment.find("(ignored by octarc)"), std::string::npos) << k.name;
    }
  }
  EXPECT_GT(ignored, 10);
}

}  // namespace
}  // namespace octarc::sexcompat
