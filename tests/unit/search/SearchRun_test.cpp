// A whole search of one image (searchImage, searchSummaryLines, writeSearchOutputs) on a
// hand-made scene whose candidates follow from the drawing (tests/support/ArcScene.h): an arc
// about a round lens galaxy and a straight bar pass the E_IMAGE grid, the lens galaxy and a
// round star do not. Counts, positions and areas are worked out here from the scene.
#include "octarc/search/SearchRun.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "ArcScene.h"
#include "ExpectError.h"
#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kWidthPix = 150, kHeightPix = 120;
constexpr double kScaleArcsec = 0.2;
// A pixel of 0.2" is (0.2 / 3600)^2 deg2: the whole image is 18000 / 3.24e8 = 1 / 18000 deg2.
constexpr double kPixelDeg2 = (kScaleArcsec / 3600.0) * (kScaleArcsec / 3600.0);

// The drawn objects (0-based centres). The arc spans +-50 degrees about +x on a ring of 15 px
// (3") about the lens galaxy: its centroid lies R sin(phi) / phi from the ring's centre.
constexpr double kLensX = 45, kLensY = 60, kArcRadiusPix = 15, kArcHalfOpeningDeg = 50;
constexpr double kBarX = 110, kBarY = 30, kBarLengthPix = 24;
constexpr double kStarX = 110, kStarY = 95;

double arcCentroidX() {
  const double phi = kArcHalfOpeningDeg * std::numbers::pi / 180.0;
  return kLensX + kArcRadiusPix * std::sin(phi) / phi;
}

// The scene on unit noise; with `wcs`, a north-up TAN header of 0.2" pixels.
std::string writeScene(const fs::path& path, bool wcs = true) {
  ImageF image = test::noiseImage(kWidthPix, kHeightPix, 11);
  test::addRoundGalaxy(image, kLensX, kLensY, 2.5, 150.0);
  test::addArc(image, kLensX, kLensY, kArcRadiusPix, 0.0, kArcHalfOpeningDeg, 1.0, 40.0);
  test::addBar(image, kBarX, kBarY, kBarLengthPix, 0.0, 1.0, 40.0);
  test::addRoundGalaxy(image, kStarX, kStarY, 1.5, 100.0);
  const FitsHeader header =
      wcs ? test::tanImageHeader(kWidthPix, kHeightPix, 75.5, 60.5, 150.0, 2.0, kScaleArcsec)
          : test::imageHeader(int(kWidthPix), int(kHeightPix));
  return test::writeSceneImage(path, image, header);
}

// The settings of a search of the scene in `dir` into dir/out, with one report space that holds
// the curved arc (ARCNESS about 0.15) and not the straight bar (about 0).
SearchRunSettings sceneSettings(const fs::path& dir, bool wcs = true) {
  SearchRunSettings s = test::sceneSearchSettings(
      writeScene(dir / "scene.fits", wcs), test::writeElongationGrid(dir / "elongation.grid.fits"),
      (dir / "out").string());
  s.search.reportSpaces = {SearchSpace("curved", "ARCNESS > 0.05")};
  return s;
}

// The candidate nearest the 1-based position (x, y), or null when none lies within 2 px.
const Candidate* candidateNear(const SearchRun& run, double xPix, double yPix) {
  const int x = run.catalog.findColumn("X_IMAGE"), y = run.catalog.findColumn("Y_IMAGE");
  for (const Candidate& c : run.result.candidates) {
    const auto row = std::int64_t(c.row);
    if (std::hypot(run.catalog.value(row, x) - xPix, run.catalog.value(row, y) - yPix) < 2.0) {
      return &c;
    }
  }
  return nullptr;
}

::testing::AssertionResult hasLine(const std::vector<std::string>& lines,
                                   const std::string& wanted) {
  if (std::find(lines.begin(), lines.end(), wanted) != lines.end()) {
    return ::testing::AssertionSuccess();
  }
  ::testing::AssertionResult failure = ::testing::AssertionFailure();
  failure << "no line \"" << wanted << "\" among:";
  for (const std::string& line : lines) failure << "\n  \"" << line << "\"";
  return failure;
}

TEST(SearchRun, TheArcAndTheBarAreTheCandidatesNotTheRoundGalaxies) {
  const fs::path dir = test::scratchDir();
  const SearchRunSettings settings = sceneSettings(dir);
  const SearchRun run = searchImage(settings, {});

  // One level at 5 sigma, no filter: the four drawn objects and nothing of the noise.
  EXPECT_EQ(run.catalog.rows(), 4);
  EXPECT_NEAR(run.pixelScaleArcsec, kScaleArcsec, 1e-9);
  EXPECT_TRUE(run.warnings.empty()) << run.warnings.front();
  ASSERT_EQ(run.result.candidates.size(), 2u);

  // The arc at its centroid (1-based), its lens the galaxy at the ring's centre, theta_E the
  // ring's radius (15 px = 3") from the circle fitted to its pixels. The fit of +-50 degrees of
  // a ring trades centre for radius along the arc's axis: half a pixel of either is the noise.
  const Candidate* arc = candidateNear(run, arcCentroidX() + 1, kLensY + 1);
  ASSERT_NE(arc, nullptr);
  // Within 0.3 px: the Gaussian cross-section puts the flux-weighted radius sigma^2 / R = 0.07
  // px outside the ring.
  const int x = run.catalog.findColumn("X_IMAGE"), y = run.catalog.findColumn("Y_IMAGE");
  EXPECT_NEAR(run.catalog.value(std::int64_t(arc->row), x), arcCentroidX() + 1, 0.3);
  EXPECT_NEAR(run.catalog.value(std::int64_t(arc->row), y), kLensY + 1, 0.3);
  ASSERT_TRUE(arc->lens);
  EXPECT_NEAR(arc->lens->xPix, kLensX + 1, 0.1);
  EXPECT_NEAR(arc->lens->yPix, kLensY + 1, 0.1);
  ASSERT_TRUE(arc->curvature);
  EXPECT_NEAR(arc->curvature->xCentre, kLensX + 1, 1.0);
  EXPECT_NEAR(arc->curvature->yCentre, kLensY + 1, 1.0);
  EXPECT_NEAR(arc->curvature->radius, kArcRadiusPix, 1.0);
  EXPECT_EQ(arc->lens->thetaEMethod, ThetaEMethod::kCurvature);
  EXPECT_NEAR(arc->lens->einsteinRadiusArcsec, kArcRadiusPix * kScaleArcsec, 0.2);
  EXPECT_EQ(arc->flags & (kCandidateDarkLens | kCandidateNoWcs | kCandidateNoCurvature), 0);
  EXPECT_EQ(arc->spaces, 1u);  // curved
  EXPECT_FALSE(arc->name.empty());
  EXPECT_TRUE(std::isfinite(arc->raDeg) && std::isfinite(arc->decDeg));

  // The bar at its centre: no galaxy within LENS_RADIUS (6" = 30 px; the star lies 65 px away)
  // and too straight for a side, so a possible dark lens; not curved.
  const Candidate* bar = candidateNear(run, kBarX + 1, kBarY + 1);
  ASSERT_NE(bar, nullptr);
  EXPECT_NEAR(run.catalog.value(std::int64_t(bar->row), x), kBarX + 1, 0.1);
  EXPECT_NEAR(run.catalog.value(std::int64_t(bar->row), y), kBarY + 1, 0.1);
  EXPECT_FALSE(bar->lens);
  EXPECT_NE(bar->flags & kCandidateDarkLens, 0);
  EXPECT_NE(bar->flags & kCandidateSideUnknown, 0);
  EXPECT_EQ(bar->spaces, 0u);

  // The whole image searched: 150 x 120 pixels, 1 / 18000 deg2 (TAN this near its tangent
  // point: equal to 1e-6); 2 of the 4 rows selected.
  const SearchSummary& summary = run.result.summary;
  EXPECT_EQ(summary.searchedPixels, kWidthPix * kHeightPix);
  EXPECT_NEAR(summary.searchedAreaDeg2 / (double(kWidthPix * kHeightPix) * kPixelDeg2), 1.0, 1e-6);
  EXPECT_EQ(summary.objectsSearched, 4);
  EXPECT_EQ(summary.rowsSearched, 4);
  EXPECT_EQ(summary.rowsSelected, 2);
  EXPECT_EQ(summary.candidates, 2);

  // The summary lines say the same counts: 2 candidates on 1 / 18000 deg2 are 36000 per deg2.
  const std::vector<std::string> lines = searchSummaryLines(run, settings);
  EXPECT_EQ(lines.front(), "Image " + settings.run.imagePaths[0] + ", grid " + settings.gridPath);
  EXPECT_TRUE(hasLine(lines, "18000 pixels searched (0.00006 deg2)"));
  EXPECT_TRUE(hasLine(lines,
                      "4 objects (4 rows at all levels) searched; 2 rows selected "
                      "(50.000% rejected)"));
  EXPECT_TRUE(hasLine(lines, "2 candidate(s), 36000.0 per deg2; 1 without a visible lens"));
  EXPECT_TRUE(hasLine(lines, "  curved (ARCNESS > 0.05): 1 candidate(s), 18000.0 per deg2"));
}

TEST(SearchRun, MaskNameTakesTheBarAndItsPixelsOutOfTheSearch) {
  const fs::path dir = test::scratchDir();
  SearchRunSettings settings = sceneSettings(dir);
  // An excluded 40 x 20 box about the bar, its edges between pixels: 1-based x 91..130 and
  // y 21..40, 800 pixels.
  settings.maskPath = test::writeTextFile(dir / "mask.reg",
                                          "# Region file format: DS9 version 4.1\n"
                                          "image\n"
                                          "-box(110.5,30.5,40,20,0)\n");
  const SearchRun run = searchImage(settings, {});

  ASSERT_EQ(run.result.candidates.size(), 1u);
  EXPECT_NE(candidateNear(run, arcCentroidX() + 1, kLensY + 1), nullptr);
  const SearchSummary& summary = run.result.summary;
  EXPECT_EQ(summary.searchedPixels, kWidthPix * kHeightPix - 800);
  EXPECT_NEAR(summary.searchedAreaDeg2 / (17200.0 * kPixelDeg2), 1.0, 1e-6);
  // The bar's row is detected but not searched.
  EXPECT_EQ(run.catalog.rows(), 4);
  EXPECT_EQ(summary.rowsSearched, 3);
  EXPECT_EQ(summary.objectsSearched, 3);
  EXPECT_EQ(summary.rowsSelected, 1);

  const std::vector<std::string> lines = searchSummaryLines(run, settings);
  EXPECT_TRUE(hasLine(lines, "17200 pixels searched (0.00005 deg2)"));
  EXPECT_TRUE(hasLine(lines,
                      "3 objects (3 rows at all levels) searched; 1 rows selected "
                      "(66.667% rejected)"));
  EXPECT_TRUE(hasLine(lines, "  curved (ARCNESS > 0.05): 1 candidate(s), 18837.2 per deg2"));
}

// Without a WCS the same candidates, each flagged, with NaN sky positions and no name; the area
// from PIXEL_SCALE. Without PIXEL_SCALE either there is no area: a configuration error.
TEST(SearchRun, WithoutWcsCandidatesAreFlaggedAndPixelScaleIsNeeded) {
  const fs::path dir = test::scratchDir();
  SearchRunSettings settings = sceneSettings(dir, false);
  settings.run.pixelScaleArcsec = kScaleArcsec;
  const SearchRun run = searchImage(settings, {});
  ASSERT_EQ(run.result.candidates.size(), 2u);
  for (const Candidate& c : run.result.candidates) {
    EXPECT_NE(c.flags & kCandidateNoWcs, 0);
    EXPECT_TRUE(std::isnan(c.raDeg) && std::isnan(c.decDeg));
    EXPECT_TRUE(c.name.empty());
  }
  EXPECT_NE(candidateNear(run, kBarX + 1, kBarY + 1), nullptr);
  EXPECT_NEAR(run.result.summary.searchedAreaDeg2 / (18000.0 * kPixelDeg2), 1.0, 1e-12);
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find("has no celestial WCS"), std::string::npos) << run.warnings[0];
  EXPECT_TRUE(hasLine(searchSummaryLines(run, settings),
                      "18000 pixels searched (0.00006 deg2, from PIXEL_SCALE: no WCS)"));

  settings.run.pixelScaleArcsec = 0.0;
  test::expectError<ConfigError>([&] { searchImage(settings, {}); },
                                 {settings.run.imagePaths[0], "set PIXEL_SCALE"});
  EXPECT_FALSE(fs::exists(settings.outputDir));
}

TEST(SearchRun, OutputsAreWrittenTogetherAndAgreeWithTheRun) {
  const fs::path dir = test::scratchDir();
  const SearchRunSettings settings = sceneSettings(dir);
  const SearchRun run = searchImage(settings, {});
  ASSERT_EQ(run.result.candidates.size(), 2u);
  std::int64_t stamps = 0;
  writeSearchOutputs(run, settings, [&](std::int64_t done, std::int64_t) { stamps = done; }, {});

  const fs::path out = settings.outputDir;
  EXPECT_EQ(test::fileNames(out),
            (std::set<std::string>{kSearchMarkerFile, "candidates.cat", "candidates.fits",
                                   "candidates.reg", "index.html", "stamps", "summary.txt"}));
  EXPECT_EQ(test::fileNames(out / "stamps"),
            (std::set<std::string>{"0001.png", "0002.png", "0001.fits", "0002.fits"}));
  EXPECT_EQ(stamps, 2);
  EXPECT_EQ(test::readFile(out / kSearchMarkerFile), kSearchMarkerText);
  // Nothing but the inputs and the output beside it: the temporary directory is gone.
  EXPECT_EQ(test::fileNames(dir),
            (std::set<std::string>{"elongation.grid.fits", "out", "scene.fits"}));

  // Two candidates in the catalog, one of them the bar at its centre.
  const FitsTable table = readFitsTable((out / "candidates.fits").string(), "LDAC_OBJECTS");
  ASSERT_EQ(table.rows(), 2);
  EXPECT_EQ(table.integer("NCANDID"), 2);
  const std::vector<double> xs = table.doubles("X_IMAGE"), ys = table.doubles("Y_IMAGE");
  int bars = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    bars += std::hypot(xs[i] - (kBarX + 1), ys[i] - (kBarY + 1)) < 0.1;
  }
  EXPECT_EQ(bars, 1);
  std::string summary;
  for (const std::string& line : searchSummaryLines(run, settings)) summary += line + "\n";
  EXPECT_EQ(test::readFile(out / "summary.txt"), summary);
  EXPECT_NE(summary.find("\n2 candidate(s), "), std::string::npos) << summary;
}

// A failure while the directory is filled leaves none behind, and names OUTPUT_DIR, not the
// temporary directory it was written in.
TEST(SearchRun, AFailedWriteLeavesNoOutputDirectory) {
  const fs::path dir = test::scratchDir();
  const SearchRunSettings settings = sceneSettings(dir);
  const SearchRun run = searchImage(settings, {});
  test::expectIoError(
      [&] {
        writeSearchOutputs(run, settings, {}, {}, [](const std::string& tempDir) {
          throw IoError(tempDir + "/extra.txt: cannot write (No space left on device)");
        });
      },
      {settings.outputDir + "/extra.txt: cannot write"});
  EXPECT_EQ(test::fileNames(dir), (std::set<std::string>{"elongation.grid.fits", "scene.fits"}));
}

TEST(SearchRun, AMissingImageOrGridIsAnErrorNamingItAndNothingIsWritten) {
  const fs::path dir = test::scratchDir();
  const SearchRunSettings settings = sceneSettings(dir);

  SearchRunSettings noImage = settings;
  noImage.run.imagePaths = {(dir / "missing.fits").string()};
  test::expectIoError([&] { searchImage(noImage, {}); }, {noImage.run.imagePaths[0]});

  SearchRunSettings noGrid = settings;
  noGrid.gridPath = (dir / "missing.grid.fits").string();
  test::expectIoError([&] { searchImage(noGrid, {}); }, {"GRID_NAME", noGrid.gridPath});

  SearchRunSettings noMask = settings;
  noMask.maskPath = (dir / "missing.reg").string();
  test::expectIoError([&] { searchImage(noMask, {}); }, {noMask.maskPath, "cannot open"});

  EXPECT_EQ(test::fileNames(dir), (std::set<std::string>{"elongation.grid.fits", "scene.fits"}));
}

// OUTPUT_DIR is replaced whole: a directory that is not a search's, or one holding an input, is
// refused before anything is read, and left as it was.
TEST(SearchRun, AnOutputDirectoryThatIsNotASearchsIsRefusedAndKept) {
  const fs::path dir = test::scratchDir();
  SearchRunSettings settings = sceneSettings(dir);
  fs::create_directories(settings.outputDir);
  test::writeTextFile(fs::path(settings.outputDir) / "notes.txt", "my notes\n");
  test::expectError<ConfigError>([&] { searchImage(settings, {}); }, {settings.outputDir});
  EXPECT_EQ(test::fileNames(settings.outputDir), (std::set<std::string>{"notes.txt"}));

  settings.outputDir = dir.string();
  test::expectError<ConfigError>([&] { searchImage(settings, {}); },
                                 {"OUTPUT_DIR " + dir.string(), settings.run.imagePaths[0]});
  EXPECT_EQ(test::fileNames(dir),
            (std::set<std::string>{"elongation.grid.fits", "out", "scene.fits"}));
}

}  // namespace
}  // namespace octarc
