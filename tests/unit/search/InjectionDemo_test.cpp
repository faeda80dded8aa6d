// The demo's run as a library call: a small simulated field with two lenses searched end to end,
// and the inputs checked before anything is made.
#include "octarc/search/InjectionDemo.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "ExpectError.h"
#include "TestFiles.h"
#include "TestPaths.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

int lineCount(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines;
}

InjectionDemoSettings smallDemo(const fs::path& out) {
  InjectionDemoSettings s;
  s.field.sizePix = 512;
  s.field.lensCount = 2;
  s.field.seed = 1;
  s.field.threads = 2;
  s.field.minEinsteinRadiusArcsec = kDemoMinEinsteinRadiusArcsec;
  s.outDir = out.string();
  return s;
}

TEST(InjectionDemo, SmallFieldSearchedAndEveryOutputWritten) {
  const fs::path out = test::scratchDir() / "demo";
  const InjectionDemoSettings settings = smallDemo(out);
  const InjectionDemo demo = runInjectionDemo(settings);

  for (const char* name :
       {"field.fits", "field.weight.fits", "field.truth.txt", "field.ldac", "injection-systems.txt",
        "injection-candidates.txt", "candidates/candidates.fits", "candidates/index.html"}) {
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  }
  // Both injected systems, each at least as large as asked for.
  ASSERT_EQ(demo.match.systems.size(), 2u);
  for (const InjectedLensOutcome& s : demo.match.systems) {
    EXPECT_GE(s.einsteinRadiusArcsec, kDemoMinEinsteinRadiusArcsec);
  }
  // A header line, then one line per system and one per candidate.
  EXPECT_EQ(lineCount(test::readFile(out / "injection-systems.txt")), 1 + 2);
  EXPECT_EQ(lineCount(test::readFile(out / "injection-candidates.txt")),
            1 + int(demo.run.result.candidates.size()));
  // LENS_SCORE's prior is the field's own density: 2 lenses on 512 px of 0.257".
  const double sideDeg = 512 * 0.257 / 3600.0;
  EXPECT_NEAR(demo.search.search.lensDensityPerDeg2, 2.0 / (sideDeg * sideDeg), 1e-6);
  // The default selection: the shipped model, LENS_SCORE >= 0.01, S/N > 40.
  EXPECT_EQ(demo.search.search.method, SelectionMethod::Trees);
  EXPECT_DOUBLE_EQ(demo.search.search.scoreMin, 0.01);
  EXPECT_DOUBLE_EQ(demo.search.search.snrMin, 40.0);

  std::ostringstream report;
  printInjectionDemoReport(report, settings, demo);
  EXPECT_EQ(report.str().rfind(
                "octarc demo: a simulated survey field with 2 injected galaxy-galaxy lenses\n", 0),
            0u)
      << report.str();
  EXPECT_NE(report.str().find("  512 x 512 px of 0.257\""), std::string::npos) << report.str();
}

TEST(InjectionDemo, UnreadableModelStopsTheRunBeforeAnythingIsMade) {
  const fs::path out = test::scratchDir() / "demo";
  InjectionDemoSettings settings = smallDemo(out);
  settings.modelPath = (out.parent_path() / "missing.model.fits").string();
  test::expectIoError([&] { runInjectionDemo(settings); },
                      {settings.modelPath, "cannot open as FITS"});
  EXPECT_FALSE(fs::exists(out));
}

TEST(InjectionDemo, OutputOverTheInjectedImageIsRefused) {
  const fs::path out = test::scratchDir() / "demo";
  InjectionDemoSettings settings = smallDemo(out);
  settings.real.imagePath = (out / "field.fits").string();
  test::expectError<ConfigError>([&] { runInjectionDemo(settings); }, {"--into image"});
  EXPECT_FALSE(fs::exists(out / "field.fits"));
}

TEST(InjectionDemo, UnknownLensLightIsRefused) {
  const fs::path out = test::scratchDir() / "demo";
  InjectionDemoSettings settings = smallDemo(out);
  settings.lensLight = "EVERYWHERE";
  EXPECT_THROW(runInjectionDemo(settings), ConfigError);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace octarc
