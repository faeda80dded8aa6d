#include "octarc/sexcompat/ParamFile.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc::sexcompat {
namespace {

TEST(ParamFile, NamesSizesCommentsAndOrder) {
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "a.param",
                                               "# comment\n"
                                               "NUMBER\n"
                                               "\n"
                                               "   X_IMAGE   # trailing comment\n"
                                               "FLUX_APER(3)\n"
                                               "MAG_APER[2]\n"
                                               "VIGNET(31,31)\n"
                                               "FLUX_RADIUS{4}\n"
                                               "VECTOR_ASSOC( 5 ) # with blanks\n"
                                               "\tFLAGS\n"
                                               "NUMBER\n"
                                               "X_IMAGE(2)\n"
                                               "#X2_IMAGE\n");
  const std::vector<ParamRequest> r = readParamFile(path);
  ASSERT_EQ(r.size(), 8u);
  EXPECT_EQ(r[0].name, "NUMBER");
  EXPECT_TRUE(r[0].sizes.empty());
  EXPECT_EQ(r[0].line, 2);
  EXPECT_EQ(r[1].name, "X_IMAGE");
  EXPECT_EQ(r[1].line, 4);
  EXPECT_EQ(r[2].name, "FLUX_APER");
  EXPECT_EQ(r[2].sizes, std::vector<int>{3});
  EXPECT_EQ(r[3].name, "MAG_APER");
  EXPECT_EQ(r[3].sizes, std::vector<int>{2});
  EXPECT_EQ(r[4].name, "VIGNET");
  EXPECT_EQ(r[4].sizes, (std::vector<int>{31, 31}));
  EXPECT_EQ(r[5].sizes, std::vector<int>{4});
  EXPECT_EQ(r[6].name, "VECTOR_ASSOC");
  EXPECT_EQ(r[6].sizes, std::vector<int>{5});
  EXPECT_EQ(r[7].name, "FLAGS");
  EXPECT_EQ(r[7].line, 10);
}

std::string paramError(const std::string& text) {
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "bad.param", "NUMBER\n" + text + "\n");
  try {
    readParamFile(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamFile, BadSizesNameFileAndLine) {
  std::string msg = paramError("FLUX_APER(0)");
  EXPECT_NE(msg.find("bad.param:2: 'FLUX_APER'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("positive"), std::string::npos) << msg;
  msg = paramError("FLUX_APER(x)");
  EXPECT_NE(msg.find("bad.param:2: 'FLUX_APER'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'x'"), std::string::npos) << msg;
  msg = paramError("VIGNET(3,-1)");
  EXPECT_NE(msg.find("bad.param:2"), std::string::npos) << msg;
  msg = paramError("FLUX_APER(3a)");
  EXPECT_NE(msg.find("'3a'"), std::string::npos) << msg;
  // The column holds the product of the sizes; 65536 x 65536 does not fit in an int.
  msg = paramError("VECTOR_ASSOC(65536,65536)");
  EXPECT_NE(msg.find("bad.param:2: 'VECTOR_ASSOC': vector of more than 2147483647 elements"),
            std::string::npos)
      << msg;
  EXPECT_EQ(paramError("VECTOR_ASSOC(32768,65535)"), "");  // 2147450880 elements
  // A name with an escape sequence is shown escaped.
  msg = paramError("\x1bX(0)");
  EXPECT_NE(msg.find("bad.param:2: '\\x1BX'"), std::string::npos) << msg;
}

TEST(ParamFile, MissingFileIsAnIoError) {
  try {
    readParamFile("/nonexistent/x.param");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.param"), std::string::npos);
  }
}

TEST(ParamFile, EverySourceExtractorParameterReads) {
  // `source-extractor -dp` prints every known parameter as "#NAME  description [unit]". Written
  // back as "NAME  # description [unit]", the file must give one request per line, in order.
  const auto dir = test::scratchDir();
  const std::string dp = (dir / "dp.txt").string();
  if (std::system(("source-extractor -dp > " + dp + " 2>/dev/null").c_str()) != 0)
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  std::ifstream in(dp);
  std::ofstream out(dir / "all.param");
  std::string line;
  std::vector<std::string> names;
  while (std::getline(in, line)) {
    if (line.size() < 2 || line[0] != '#') continue;
    const std::size_t nameEnd = line.find(' ');
    names.push_back(line.substr(1, nameEnd - 1));
    out << names.back() << "  # " << line.substr(nameEnd) << "\n";
  }
  out.close();
  const std::vector<ParamRequest> r = readParamFile((dir / "all.param").string());
  ASSERT_EQ(r.size(), names.size());
  EXPECT_GT(r.size(), 400u);
  for (std::size_t i = 0; i < r.size(); ++i) EXPECT_EQ(r[i].name, names[i]);
  // octarc's own list of SExtractor's parameters is exactly this one.
  for (const std::string& name : names) EXPECT_TRUE(isSextractorParameter(name)) << name;
}

TEST(ParamFile, NamesSExtractorDoesNotKnowAreNotItsParameters) {
  EXPECT_TRUE(isSextractorParameter("MAG_AUTO"));
  EXPECT_TRUE(isSextractorParameter("FLUX_RADIUS"));
  EXPECT_TRUE(isSextractorParameter("NUMBER"));
  EXPECT_FALSE(isSextractorParameter("ARCNESS"));  // octarc's own
  EXPECT_FALSE(isSextractorParameter("MAG_AUTOX"));
  EXPECT_FALSE(isSextractorParameter("mag_auto"));  // .param names are upper case
  EXPECT_FALSE(isSextractorParameter(""));
}

}  // namespace
}  // namespace octarc::sexcompat
