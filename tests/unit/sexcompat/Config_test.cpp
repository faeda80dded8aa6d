#include "octarc/sexcompat/Config.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc::sexcompat {
namespace {

using Kind = KeySpec::Kind;

KeySpec key(const char* name, Kind kind, std::vector<std::string> defaults, int minCount = 1,
            int maxCount = 1) {
  KeySpec k;
  k.name = name;
  k.kind = kind;
  k.defaults = std::move(defaults);
  k.minCount = minCount;
  k.maxCount = maxCount;
  return k;
}

std::vector<KeySpec> schema() {
  KeySpec thresh = key("DETECT_THRESH", Kind::Float, {"1.5"}, 1, 2);
  thresh.minValue = 0.0;
  thresh.maxValue = 100.0;
  KeySpec minArea = key("DETECT_MINAREA", Kind::Int, {"5"});
  minArea.minValue = 1;
  minArea.maxValue = 1e6;
  KeySpec type = key("THRESH_TYPE", Kind::Keyword, {"RELATIVE"}, 1, 2);
  type.keywords = {"RELATIVE", "ABSOLUTE"};
  KeySpec sel = key("ASSOCSELEC_TYPE", Kind::Keyword, {"MATCHED"});
  sel.keywords = {"ALL", "MATCHED", "-MATCHED"};
  KeySpec back = key("BACK_VALUE", Kind::Float, {"0.0"}, 1, 2);
  KeySpec filterThresh = key("FILTER_THRESH", Kind::Float, {}, 0, 2);
  filterThresh.expertOnly = true;
  KeySpec filter = key("FILTER", Kind::Bool, {"Y"});
  filter.comment = "apply the filter";
  KeySpec name = key("CATALOG_NAME", Kind::String, {"test.cat"});
  name.comment = "output catalog\nsecond comment line";
  KeySpec checks = key("CHECKIMAGE_NAME", Kind::String, {"check.fits"}, 0, 17);
  return {thresh, minArea, type, sel, back, filterThresh, filter, name, checks};
}

TEST(Config, DefaultsWhenNoFileAndNoOverrides) {
  const Config c = Config::load(schema(), "", {}, nullptr);
  EXPECT_DOUBLE_EQ(c.getDouble("DETECT_THRESH"), 1.5);
  EXPECT_EQ(c.getInt("DETECT_MINAREA"), 5);
  EXPECT_EQ(c.getString("THRESH_TYPE"), "RELATIVE");
  EXPECT_TRUE(c.getBool("FILTER"));
  EXPECT_EQ(c.count("FILTER_THRESH"), 0);
  EXPECT_FALSE(c.isExplicit("DETECT_THRESH"));
}

TEST(Config, FileSeparatorsCommentsCaseAndLists) {
  const auto dir = test::scratchDir();
  const std::string path =
      test::writeTextFile(dir / "a.sex",
                          "# a comment line\n"
                          "   # indented comment\n"
                          "\n"
                          "detect_thresh=2.5;3   # two values, inline comment\n"
                          "DETECT_MINAREA\t0x10\n"
                          "Thresh_Type absolute , relative\n"
                          "FILTER no\n"
                          "CATALOG_NAME \"out.cat\"\n"
                          "CHECKIMAGE_NAME seg1.fits,seg2.fits seg3.fits\n");
  std::vector<std::string> warnings;
  const Config c = Config::load(schema(), path, {}, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(c.getDoubles("DETECT_THRESH"), (std::vector<double>{2.5, 3.0}));
  EXPECT_EQ(c.getInt("DETECT_MINAREA"), 16);  // strtol base 0, as SExtractor
  EXPECT_EQ(c.getStrings("THRESH_TYPE"), (std::vector<std::string>{"ABSOLUTE", "RELATIVE"}));
  EXPECT_FALSE(c.getBool("FILTER"));
  EXPECT_EQ(c.getString("CATALOG_NAME"), "out.cat");
  EXPECT_EQ(c.getStrings("CHECKIMAGE_NAME"),
            (std::vector<std::string>{"seg1.fits", "seg2.fits", "seg3.fits"}));
  EXPECT_TRUE(c.isExplicit("DETECT_THRESH"));
  EXPECT_FALSE(c.isExplicit("BACK_VALUE"));
}

TEST(Config, OrderDefaultsThenFileThenCommandLineLastWins) {
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "a.sex",
                                               "DETECT_THRESH 2.0\n"
                                               "DETECT_MINAREA 3\n"
                                               "DETECT_MINAREA 4\n");
  const Config c = Config::load(
      schema(), path, {{"DETECT_THRESH", "7"}, {"detect_thresh", "8"}, {"FILTER", "N"}}, nullptr);
  EXPECT_DOUBLE_EQ(c.getDouble("DETECT_THRESH"), 8.0);
  EXPECT_EQ(c.getInt("DETECT_MINAREA"), 4);
  EXPECT_FALSE(c.getBool("FILTER"));
  EXPECT_TRUE(c.isExplicit("FILTER"));
}

TEST(Config, UnknownKeyInFileWarnsButOnCommandLineFails) {
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "a.sex", "NO_SUCH_KEY 3\nFILTER N\n");
  std::vector<std::string> warnings;
  const Config c = Config::load(schema(), path, {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("a.sex:1"), std::string::npos);
  EXPECT_NE(warnings[0].find("NO_SUCH_KEY"), std::string::npos);
  EXPECT_FALSE(c.getBool("FILTER"));
  try {
    Config::load(schema(), "", {{"NO_SUCH_KEY", "3"}}, nullptr);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown keyword"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("NO_SUCH_KEY"), std::string::npos) << e.what();
  }
}

// A key octarc does not act on warns once when it is set: always on the command line, in a file
// only to another value than its default (a template lists every key at its default).
TEST(Config, IgnoredKeysThatAreSetWarnOnce) {
  std::vector<KeySpec> keys = schema();
  KeySpec nthresh = key("DEBLEND_NTHRESH", Kind::Int, {"32"});
  nthresh.ignored = true;
  KeySpec clean = key("CLEAN", Kind::Bool, {"Y"});
  clean.ignored = true;
  KeySpec xml = key("XML_NAME", Kind::String, {"sex.xml"});
  xml.ignored = true;
  keys.insert(keys.end(), {nthresh, clean, xml});
  const auto dir = test::scratchDir();
  std::vector<std::string> warnings;
  (void)Config::load(keys, "", {}, &warnings);
  EXPECT_TRUE(warnings.empty());
  const std::string path =
      test::writeTextFile(dir / "ignored.sex", "DEBLEND_NTHRESH 32\nCLEAN N\nXML_NAME sex.xml\n");
  (void)Config::load(keys, path, {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], path + ":2: CLEAN is ignored by octarc (setting it has no effect)");
  warnings.clear();
  (void)Config::load(keys, path, {{"DEBLEND_NTHRESH", "64"}, {"CLEAN", "Y"}, {"clean", "N"}},
                     &warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0],
            "command line: -DEBLEND_NTHRESH is ignored by octarc (setting it has no effect)");
  EXPECT_EQ(warnings[1], "command line: -CLEAN is ignored by octarc (setting it has no effect)");
}

// Runs load() and returns the error message ("" if none).
std::string loadError(const std::string& file,
                      std::vector<std::pair<std::string, std::string>> ov) {
  try {
    Config::load(schema(), file, ov, nullptr);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, MalformedValuesNameKeyValueAndPlace) {
  const auto dir = test::scratchDir();
  const auto file = [&](const std::string& text) {
    return test::writeTextFile(dir / "bad.sex", "FILTER Y\n" + text + "\n");
  };
  std::string msg = loadError(file("DETECT_THRESH abc"), {});
  EXPECT_NE(msg.find("bad.sex:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("DETECT_THRESH"), std::string::npos) << msg;
  EXPECT_NE(msg.find("abc"), std::string::npos) << msg;

  msg = loadError(file("DETECT_MINAREA 2.5"), {});
  EXPECT_NE(msg.find("not an integer"), std::string::npos) << msg;
  msg = loadError(file("DETECT_MINAREA 0"), {});
  EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  msg = loadError(file("DETECT_THRESH 101"), {});
  EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  msg = loadError(file("DETECT_THRESH 1,2,3"), {});
  EXPECT_NE(msg.find("expected 1 to 2 value(s), got 3"), std::string::npos) << msg;
  msg = loadError(file("THRESH_TYPE SIGMA"), {});
  EXPECT_NE(msg.find("RELATIVE, ABSOLUTE"), std::string::npos) << msg;
  msg = loadError(file("FILTER maybe"), {});
  EXPECT_NE(msg.find("Y or N"), std::string::npos) << msg;
  msg = loadError(file("DETECT_MINAREA"), {});
  EXPECT_NE(msg.find("got 0"), std::string::npos) << msg;
  msg = loadError(file("DETECT_THRESH nan"), {});
  EXPECT_NE(msg.find("not a number"), std::string::npos) << msg;

  msg = loadError("", {{"DETECT_MINAREA", "-3"}});
  EXPECT_NE(msg.find("command line"), std::string::npos) << msg;
  EXPECT_NE(msg.find("DETECT_MINAREA '-3'"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line";
}

// A bare "WEIGHT_TYPE" line or "WEIGHT_THRESH ," used to reach an .at(0) on an empty list (an
// internal error, exit 3). An empty list is "not given", as in SExtractor.
TEST(Config, EmptyListMeansNotGiven) {
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "bare.sex",
                                               "CHECKIMAGE_NAME a.fits\n"
                                               "CHECKIMAGE_NAME\n"
                                               "FILTER_THRESH ,\n"
                                               "FILTER_THRESH ; # only separators\n");
  const Config c = Config::load(schema(), path, {{"CHECKIMAGE_NAME", ""}}, nullptr);
  EXPECT_EQ(c.getStrings("CHECKIMAGE_NAME"), (std::vector<std::string>{"a.fits"}));
  EXPECT_TRUE(c.isExplicit("CHECKIMAGE_NAME"));  // from line 1; the bare line 2 changes nothing
  EXPECT_EQ(c.count("FILTER_THRESH"), 0);
  EXPECT_FALSE(c.isExplicit("FILTER_THRESH"));
  const Config d = Config::load(schema(), "", {{"CHECKIMAGE_NAME", ","}}, nullptr);
  EXPECT_EQ(d.getStrings("CHECKIMAGE_NAME"), (std::vector<std::string>{"check.fits"}));
  EXPECT_FALSE(d.isExplicit("CHECKIMAGE_NAME"));
  // Keys that need a value still say so.
  const std::string msg = loadError(test::writeTextFile(dir / "b.sex", "DETECT_THRESH ,\n"), {});
  EXPECT_NE(msg.find("b.sex:1: DETECT_THRESH (empty): expected 1 to 2 value(s), got 0"),
            std::string::npos)
      << msg;
  // An index past the end is a ConfigError naming the key, never an internal error.
  EXPECT_THROW(c.getString("FILTER_THRESH"), ConfigError);
  EXPECT_THROW(c.getDouble("FILTER_THRESH", 0), ConfigError);
}

// A NUL in a file name cut it silently ("out\0x.cat" wrote "out"); an escape sequence in a
// value went raw into messages. Both are refused, naming key and place, the value escaped.
TEST(Config, ControlCharactersAreRefusedAndShownEscaped) {
  const auto dir = test::scratchDir();
  const std::string nul = test::writeTextFile(
      dir / "nul.sex", std::string("FILTER Y\nCATALOG_NAME out") + '\0' + "x.cat\n");
  std::string msg = loadError(nul, {});
  EXPECT_EQ(msg, nul + ":2: CATALOG_NAME 'out\\x00x.cat': holds a control character");
  const std::string esc = test::writeTextFile(dir / "esc.sex", "CATALOG_NAME \x1b[31mred\n");
  msg = loadError(esc, {});
  EXPECT_EQ(msg, esc + ":1: CATALOG_NAME '\\x1B[31mred': holds a control character");
  msg = loadError("", {{"CHECKIMAGE_NAME", "a.fits,b\x7f.fits"}});
  EXPECT_EQ(msg, "command line: CHECKIMAGE_NAME 'b\\x7F.fits': holds a control character");
  // Long values are cut in messages.
  msg = loadError("", {{"THRESH_TYPE", std::string(5000, 'X')}});
  EXPECT_NE(msg.find("'" + std::string(60, 'X') + "'... (5000 characters)"), std::string::npos)
      << msg;
  EXPECT_LT(msg.size(), 200u);
  // An unknown key with an escape: a warning, the key escaped.
  std::vector<std::string> warnings;
  Config::load(schema(), test::writeTextFile(dir / "k.sex", "\x1b[2JKEY 1\n"), {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("unknown keyword '\\x1B[2JKEY'"), std::string::npos) << warnings[0];
}

TEST(Config, MissingExplicitFileIsAnError) {
  const std::string msg = loadError("/nonexistent/dir/my.sex", {});
  EXPECT_NE(msg.find("/nonexistent/dir/my.sex"), std::string::npos) << msg;
}

TEST(Config, KeywordValuesAreCaseInsensitiveAndMayStartWithDash) {
  const Config c = Config::load(schema(), "", {{"ASSOCSELEC_TYPE", "-matched"}}, nullptr);
  EXPECT_EQ(c.getString("ASSOCSELEC_TYPE"), "-MATCHED");
  const Config d = Config::load(schema(), "", {{"BACK_VALUE", "-5.5,2"}}, nullptr);
  EXPECT_EQ(d.getDoubles("BACK_VALUE"), (std::vector<double>{-5.5, 2.0}));
}

TEST(Config, EnvironmentVariablesAreExpanded) {
  ::setenv("OCTARC_TEST_DIR", "/data/run1", 1);
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(
      dir / "env.sex",
      "CATALOG_NAME ${OCTARC_TEST_DIR}/cat.fits\nCHECKIMAGE_NAME $OCTARC_TEST_DIR\n");
  const Config c = Config::load(schema(), path, {}, nullptr);
  EXPECT_EQ(c.getString("CATALOG_NAME"), "/data/run1/cat.fits");
  EXPECT_EQ(c.getString("CHECKIMAGE_NAME"), "/data/run1");
  ::unsetenv("OCTARC_TEST_UNSET_VAR");
  const std::string msg = loadError("", {{"CATALOG_NAME", "$OCTARC_TEST_UNSET_VAR/x"}});
  EXPECT_NE(msg.find("OCTARC_TEST_UNSET_VAR"), std::string::npos) << msg;
}

TEST(Config, GettersRejectWrongKindIndexAndKey) {
  const Config c = Config::load(schema(), "", {}, nullptr);
  EXPECT_THROW(c.getBool("DETECT_THRESH"), ConfigError);
  EXPECT_THROW(c.getInt("DETECT_THRESH"), ConfigError);
  EXPECT_THROW(c.getDouble("DETECT_THRESH", 1), ConfigError);
  EXPECT_THROW(c.getDouble("NOT_A_KEY"), ConfigError);
  EXPECT_DOUBLE_EQ(c.getDouble("DETECT_MINAREA"), 5.0);  // an Int reads as double
}

TEST(Config, DumpIsAValidSexFileAndHonoursExpertKeys) {
  const Config c =
      Config::load(schema(), "", {{"DETECT_THRESH", "2,3"}, {"CATALOG_NAME", "x.cat"}}, nullptr);
  const std::string shortDump = c.dump(schema(), false);
  const std::string fullDump = c.dump(schema(), true);
  EXPECT_EQ(shortDump.find("FILTER_THRESH"), std::string::npos);
  EXPECT_NE(fullDump.find("FILTER_THRESH"), std::string::npos);
  EXPECT_NE(fullDump.find("# second comment line"), std::string::npos);
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "dump.sex", fullDump);
  std::vector<std::string> warnings;
  const Config back = Config::load(schema(), path, {}, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(back.getDoubles("DETECT_THRESH"), (std::vector<double>{2.0, 3.0}));
  EXPECT_EQ(back.getString("CATALOG_NAME"), "x.cat");
  EXPECT_EQ(back.count("FILTER_THRESH"), 0);
}

// Expression keys (KeySpec::expression): muparser text, kept as written.
std::vector<KeySpec> expressionSchema() {
  KeySpec cut = key("SEARCH_CUT", Kind::String, {}, 0, 1);
  cut.expression = true;
  KeySpec axes = key("GRID_AXES", Kind::String, {"ARCNESS"}, 1, 8);
  axes.expression = true;
  return {cut, axes, key("CATALOG_NAME", Kind::String, {"test.cat"})};
}

TEST(Config, ExpressionKeysKeepEveryOperatorAsWrittenInFilesAndOnTheCommandLine) {
  const auto dir = test::scratchDir();
  // Each comparison operator of muparser holds an '=', which SExtractor's separators would drop
  // ("ARCNESS >= 0.1" read as "ARCNESS > 0.1").
  for (const std::string cut : {"ARCNESS >= 0.1", "ARCNESS <= 0.15", "FLAGS == 0", "FLAGS != 4",
                                "E_IMAGE += 1", "A > 1; B < 2"}) {
    const std::string path = test::writeTextFile(dir / "a.sex", "SEARCH_CUT " + cut + "\n");
    const Config fromFile = Config::load(expressionSchema(), path, {}, nullptr);
    EXPECT_EQ(fromFile.getStrings("SEARCH_CUT"), (std::vector<std::string>{cut}));
    const Config fromCommandLine =
        Config::load(expressionSchema(), "", {{"SEARCH_CUT", cut}}, nullptr);
    EXPECT_EQ(fromCommandLine.getStrings("SEARCH_CUT"), (std::vector<std::string>{cut}));
  }
  // SExtractor's file syntax around the value still holds: '=' or blanks after the key, '"'
  // quotes, a '#' comment; a tab inside counts as a blank.
  const std::string path =
      test::writeTextFile(dir / "b.sex",
                          "search_cut = \"ARCNESS >= 0.1\t&& E_IMAGE != 0\"   # the cut\n"
                          "GRID_AXES min(ARCNESS, 0.5), log10(SNR_ISO) ,E_IMAGE\n"
                          "CATALOG_NAME=x.cat\n");
  const Config c = Config::load(expressionSchema(), path, {}, nullptr);
  EXPECT_EQ(c.getString("SEARCH_CUT"), "ARCNESS >= 0.1 && E_IMAGE != 0");
  // A list splits at commas outside parentheses only.
  EXPECT_EQ(c.getStrings("GRID_AXES"),
            (std::vector<std::string>{"min(ARCNESS, 0.5)", "log10(SNR_ISO)", "E_IMAGE"}));
  EXPECT_EQ(c.getString("CATALOG_NAME"), "x.cat");  // other keys: SExtractor's separators
  EXPECT_EQ(
      Config::load(expressionSchema(), "", {{"GRID_AXES", "ARCNESS >= 0,E_IMAGE == 1"}}, nullptr)
          .getStrings("GRID_AXES"),
      (std::vector<std::string>{"ARCNESS >= 0", "E_IMAGE == 1"}));
  // A top-level comma in a one-value key is refused, not joined into another expression.
  const std::string two = test::writeTextFile(dir / "c.sex", "SEARCH_CUT ARCNESS > 0, E > 1\n");
  try {
    Config::load(expressionSchema(), two, {}, nullptr);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("c.sex:1: SEARCH_CUT"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected 0 to 1 value(s), got 2"), std::string::npos)
        << e.what();
  }
  // The dump loads back to the same values.
  const std::string dumped = test::writeTextFile(dir / "d.sex", c.dump(expressionSchema(), true));
  const Config back = Config::load(expressionSchema(), dumped, {}, nullptr);
  EXPECT_EQ(back.getString("SEARCH_CUT"), "ARCNESS >= 0.1 && E_IMAGE != 0");
  EXPECT_EQ(back.getStrings("GRID_AXES"), c.getStrings("GRID_AXES"));
}

TEST(CommandLine, ImagesConfigFileOverridesAndDumps) {
  const CommandLine cl =
      parseCommandLine({"image.fits", "-c", "my.sex", "-detect_thresh", "3", "-BACK_VALUE", "-5",
                        "-ASSOCSELEC_TYPE", "-MATCHED", "-DETECT_THRESH", "4", "-dd"},
                       schema());
  EXPECT_EQ(cl.positional, (std::vector<std::string>{"image.fits"}));
  EXPECT_EQ(cl.configFile, "my.sex");
  ASSERT_EQ(cl.overrides.size(), 4u);
  EXPECT_EQ(cl.overrides[0], (std::pair<std::string, std::string>{"DETECT_THRESH", "3"}));
  EXPECT_EQ(cl.overrides[1], (std::pair<std::string, std::string>{"BACK_VALUE", "-5"}));
  EXPECT_EQ(cl.overrides[2], (std::pair<std::string, std::string>{"ASSOCSELEC_TYPE", "-MATCHED"}));
  EXPECT_EQ(cl.overrides[3], (std::pair<std::string, std::string>{"DETECT_THRESH", "4"}));
  EXPECT_TRUE(cl.dumpConfigFull);
  EXPECT_FALSE(cl.dumpConfig);
  const Config c = Config::load(schema(), "", cl.overrides, nullptr);
  EXPECT_DOUBLE_EQ(c.getDouble("DETECT_THRESH"), 4.0);
}

TEST(CommandLine, FlagOptions) {
  EXPECT_TRUE(parseCommandLine({"-d"}, schema()).dumpConfig);
  EXPECT_TRUE(parseCommandLine({"-dp"}, schema()).dumpParams);
  EXPECT_TRUE(parseCommandLine({"-h"}, schema()).help);
  EXPECT_TRUE(parseCommandLine({"--help"}, schema()).help);
  EXPECT_TRUE(parseCommandLine({"-v"}, schema()).version);
  EXPECT_TRUE(parseCommandLine({"--version"}, schema()).version);
  EXPECT_TRUE(parseCommandLine({"a.fits", "b.fits"}, schema()).configFile.empty());
  EXPECT_EQ(parseCommandLine({"a.fits", "b.fits"}, schema()).positional.size(), 2u);
}

std::string commandLineError(const std::vector<std::string>& args) {
  try {
    parseCommandLine(args, schema());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(CommandLine, Errors) {
  std::string msg = commandLineError({"img.fits", "-NO_SUCH_KEY", "3"});
  EXPECT_NE(msg.find("unknown keyword"), std::string::npos) << msg;
  EXPECT_NE(msg.find("NO_SUCH_KEY"), std::string::npos) << msg;
  msg = commandLineError({"img.fits", "-DETECT"});  // no abbreviations
  EXPECT_NE(msg.find("unknown keyword"), std::string::npos) << msg;
  msg = commandLineError({"img.fits", "-DETECT_THRESH"});
  EXPECT_NE(msg.find("DETECT_THRESH"), std::string::npos) << msg;
  msg = commandLineError({"img.fits", "-DETECT_THRESH=3"});
  EXPECT_NE(msg.find("two arguments"), std::string::npos) << msg;
  msg = commandLineError({"img.fits", "-c"});
  EXPECT_FALSE(msg.empty());
}

TEST(CommandLine, UnknownKeysSuggestTheNearestAndTwoDashesAreRefused) {
  std::string msg = commandLineError({"img.fits", "-DETECT_TRESH", "3"});
  EXPECT_NE(msg.find("'-DETECT_TRESH': unknown keyword (did you mean -DETECT_THRESH?)"),
            std::string::npos)
      << msg;
  msg = commandLineError({"img.fits", "-filtr", "Y"});  // case-insensitive, one edit
  EXPECT_NE(msg.find("(did you mean -FILTER?)"), std::string::npos) << msg;
  msg = commandLineError({"img.fits", "-NO_SUCH_KEY", "3"});  // nothing near: no hint
  EXPECT_EQ(msg.find("did you mean"), std::string::npos) << msg;
  EXPECT_EQ(nearestKey(schema(), "FOO"), "");
  EXPECT_EQ(nearestKey(schema(), "back_valu"), "BACK_VALUE");
  msg = commandLineError({"img.fits", "--DETECT_THRESH", "3"});
  EXPECT_NE(msg.find("'--DETECT_THRESH': keys take one dash, as in SExtractor (-DETECT_THRESH)"),
            std::string::npos)
      << msg;
  EXPECT_TRUE(parseCommandLine({"--help"}, schema()).help);  // the flags keep their two dashes
  // The same hint for a file's unknown key (a warning) and an override's (an error).
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "a.sex", "CATALOG_NAM x.cat\n");
  std::vector<std::string> warnings;
  Config::load(schema(), path, {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("ignored (did you mean CATALOG_NAME?)"), std::string::npos)
      << warnings[0];
  msg = loadError("", {{"CHECKIMAGE_NAMES", "a.fits"}});
  EXPECT_NE(msg.find("unknown keyword (did you mean -CHECKIMAGE_NAME?)"), std::string::npos) << msg;
}

}  // namespace
}  // namespace octarc::sexcompat
