#include "octarc/sexcompat/ConvFile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc::sexcompat {
namespace {

const std::filesystem::path kSextractorShare = "/usr/share/source-extractor";

TEST(ConvFile, DefaultConvIsThePyramidOverSixteen) {
  if (!std::filesystem::exists(kSextractorShare / "default.conv")) OCTARC_SKIP_MISSING();
  const ConvKernel k = readConvFile((kSextractorShare / "default.conv").string());
  ASSERT_EQ(k.width, 3);
  ASSERT_EQ(k.height, 3);
  const std::vector<float> expected{1 / 16.f, 2 / 16.f, 1 / 16.f, 2 / 16.f, 4 / 16.f,
                                    2 / 16.f, 1 / 16.f, 2 / 16.f, 1 / 16.f};
  EXPECT_EQ(k.coefficients, expected);
}

TEST(ConvFile, EveryShippedMaskLoads) {
  if (!std::filesystem::exists(kSextractorShare)) OCTARC_SKIP_MISSING();
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kSextractorShare)) {
    if (entry.path().extension() != ".conv") continue;
    ++n;
    std::vector<std::string> warnings;
    const ConvKernel k = readConvFile(entry.path().string(), &warnings);
    EXPECT_TRUE(warnings.empty()) << entry.path();
    EXPECT_EQ(k.width % 2, 1) << entry.path();
    EXPECT_EQ(k.width, k.height) << entry.path();
    EXPECT_EQ(k.coefficients.size(), static_cast<std::size_t>(k.width * k.height));
    // Every shipped mask says NORM, so the absolute values sum to 1.
    double sumAbs = 0;
    for (float c : k.coefficients) sumAbs += std::fabs(c);
    EXPECT_NEAR(sumAbs, 1.0, 1e-6) << entry.path();
    // The file name gives the size, e.g. gauss_2.0_5x5.conv.
    const std::string name = entry.path().stem().string();
    const auto x = name.rfind('x');
    if (x != std::string::npos && name != "default") {
      EXPECT_EQ(std::to_string(k.width), name.substr(x + 1)) << name;
    }
  }
  EXPECT_GE(n, 20);
}

TEST(ConvFile, NonormKeepsRawValuesAndMissingNormWarns) {
  const auto dir = test::scratchDir();
  const std::string raw =
      test::writeTextFile(dir / "raw.conv", "CONV NONORM\n# comment\n\n1 -2\n  3 4.5\n");
  std::vector<std::string> warnings;
  ConvKernel k = readConvFile(raw, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(k.width, 2);
  EXPECT_EQ(k.height, 2);
  EXPECT_EQ(k.coefficients, (std::vector<float>{1.f, -2.f, 3.f, 4.5f}));

  const std::string old = test::writeTextFile(dir / "old.conv", "CONV\n1 -3\n");
  k = readConvFile(old, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("old.conv"), std::string::npos);
  EXPECT_EQ(k.coefficients, (std::vector<float>{0.25f, -0.75f}));  // divided by |1|+|-3|
}

std::string convError(const std::string& text) {
  const auto dir = test::scratchDir();
  const std::string path = test::writeTextFile(dir / "bad.conv", text);
  try {
    readConvFile(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ConvFile, ErrorsNameFileAndLine) {
  std::string msg = convError("1 2 1\n2 4 2\n");
  EXPECT_NE(msg.find("bad.conv:1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("CONV"), std::string::npos) << msg;
  msg = convError("CONV NORM\n1 2 1\n2 4\n1 2 1\n");
  EXPECT_NE(msg.find("bad.conv:3"), std::string::npos) << msg;
  msg = convError("CONV NORM\n1 2 1\n2 x 2\n");
  EXPECT_NE(msg.find("bad.conv:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'x'"), std::string::npos) << msg;
  // User text in messages is escaped and cut: an escape sequence, a 5000-character token.
  msg = convError("CONV NORM\n1 \x1b[2J 1\n");
  EXPECT_NE(msg.find("bad.conv:2: '\\x1B[2J' is not a number"), std::string::npos) << msg;
  msg = convError("CONV NORM\n1 " + std::string(5000, '9') + "z\n");
  EXPECT_NE(msg.find("'" + std::string(60, '9') + "'... (5001 characters) is not a number"),
            std::string::npos)
      << msg;
  msg = convError("CONV NORM\n# nothing\n");
  EXPECT_NE(msg.find("no values"), std::string::npos) << msg;
  msg = convError("CONV NORM\n0 0\n0 0\n");
  EXPECT_NE(msg.find("zero"), std::string::npos) << msg;
  EXPECT_THROW(readConvFile("/nonexistent/x.conv"), IoError);
}

}  // namespace
}  // namespace octarc::sexcompat
