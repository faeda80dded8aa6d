// runBatch on the one-process cluster over three tiny tiles of hand-made sky
// (tests/support/ArcScene.h), whose candidates follow from the drawing: A and B are cut from one
// 260 x 120 field with 60 columns in common, where a bar lies that both tiles see; C lies
// elsewhere on the sky. Which tiles are searched, journaled and merged, and what the survey
// catalog holds, are worked out here from the scene.
#include "octarc/batch/BatchRun.h"

#include <gtest/gtest.h>

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
#include "octarc/batch/Journal.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

constexpr double kScaleArcsec = 0.2;
constexpr double kPixelDeg2 = (kScaleArcsec / 3600.0) * (kScaleArcsec / 3600.0);
// The field of A and B: 260 x 120 pixels; A its columns 0..159, B its columns 100..259.
constexpr std::int64_t kFieldWidthPix = 260, kTileWidthPix = 160, kHeightPix = 120;
constexpr std::int64_t kTileBOffsetPix = 100;
// C: 120 x 120 pixels, 0.1 deg east of the field.
constexpr std::int64_t kTileCSidePix = 120;

// The drawn objects, 0-based in the field (C: in C). An arc of 15 px at +-50 degrees about a
// round lens in A alone; a 20 px bar in the common columns; a bar at 60 degrees and a round
// star in B alone; a vertical bar and a round galaxy in C.
constexpr double kLensX = 40, kLensY = 60, kArcRadiusPix = 15, kArcHalfOpeningDeg = 50;
constexpr double kSharedBarX = 140, kSharedBarY = 40;
constexpr double kBarBX = 215, kBarBY = 80;
constexpr double kBarCX = 60, kBarCY = 60;

double arcCentroidX() {
  const double phi = kArcHalfOpeningDeg * std::numbers::pi / 180.0;
  return kLensX + kArcRadiusPix * std::sin(phi) / phi;
}

// Columns x0 .. x0 + width - 1 of `field`.
ImageF columnsOf(const ImageF& field, std::int64_t x0, std::int64_t width) {
  ImageF tile(width, field.height());
  for (std::int64_t y = 0; y < field.height(); ++y) {
    for (std::int64_t x = 0; x < width; ++x) tile(x, y) = field(x0 + x, y);
  }
  return tile;
}

void writeTileC(const fs::path& path) {
  ImageF image = test::noiseImage(kTileCSidePix, kTileCSidePix, 23);
  test::addBar(image, kBarCX, kBarCY, 24.0, 90.0, 1.0, 40.0);
  test::addRoundGalaxy(image, 30.0, 30.0, 2.5, 150.0);
  test::writeSceneImage(
      path, image,
      test::tanImageHeader(kTileCSidePix, kTileCSidePix, 60.5, 60.5, 150.1, 2.0, kScaleArcsec));
}

class BatchRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratchDir();
    fs::create_directories(dir_ / "images");
    ImageF field = test::noiseImage(kFieldWidthPix, kHeightPix, 17);
    test::addRoundGalaxy(field, kLensX, kLensY, 2.5, 150.0);
    test::addArc(field, kLensX, kLensY, kArcRadiusPix, 0.0, kArcHalfOpeningDeg, 1.0, 40.0);
    test::addBar(field, kSharedBarX, kSharedBarY, 20.0, 0.0, 1.0, 40.0);
    test::addBar(field, kBarBX, kBarBY, 24.0, 60.0, 1.0, 40.0);
    test::addRoundGalaxy(field, 200.0, 25.0, 1.5, 100.0);
    // The field's sky: (150, 2) at its 1-based pixel (130.5, 60.5); B's pixel x is the field's
    // x - 100.
    test::writeSceneImage(
        dir_ / "images/A.fits", columnsOf(field, 0, kTileWidthPix),
        test::tanImageHeader(kTileWidthPix, kHeightPix, 130.5, 60.5, 150.0, 2.0, kScaleArcsec));
    test::writeSceneImage(
        dir_ / "images/B.fits", columnsOf(field, kTileBOffsetPix, kTileWidthPix),
        test::tanImageHeader(kTileWidthPix, kHeightPix, 130.5 - double(kTileBOffsetPix), 60.5,
                             150.0, 2.0, kScaleArcsec));
    // C cannot be read until a test writes it.
    test::writeTextFile(dir_ / "images/C.fits", "not a FITS file\n");

    settings_.manifest = test::writeTextFile(
        dir_ / "survey.txt", "# image\nimages/A.fits\nimages/B.fits\nimages/C.fits\n");
    settings_.tile =
        test::sceneSearchSettings("", test::writeElongationGrid(dir_ / "elongation.grid.fits"), "");
    settings_.tile.search.reportSpaces = {SearchSpace("curved", "ARCNESS > 0.05")};
    // STAMPS N: the stamps are the search's own (tests/unit/search/SearchRun_test.cpp), and
    // drawing them is most of a tile's time under the sanitizers.
    settings_.tile.writeStamps = false;
    settings_.outputDir = (dir_ / "survey").string();
    settings_.requestedThreads = 1;
  }

  fs::path out() const { return settings_.outputDir; }

  // The journal's (event, tile) pairs of run `run`.
  std::set<std::pair<std::string, std::string>> journalEvents(int run) const {
    std::set<std::pair<std::string, std::string>> events;
    for (const JournalEntry& e : Journal((out() / "journal.txt").string()).read()) {
      if (e.run == run) events.insert({e.event, e.tile});
    }
    return events;
  }

  fs::path dir_;
  BatchSettings settings_;
  const Cluster cluster_;
};

// The tiles' states by name, for readable failures.
std::vector<std::string> states(const BatchReport& report) {
  std::vector<std::string> names;
  for (const TileReport& r : report.reports) {
    names.push_back(r.state == TileState::Done          ? "done"
                    : r.state == TileState::Failed      ? "failed"
                    : r.state == TileState::DoneEarlier ? "done earlier"
                                                        : "other task");
  }
  return names;
}

// Whether the survey table has a row of tile `tile` at the 1-based tile pixel (x, y).
bool hasCandidate(const FitsTable& table, const std::string& tile, double xPix, double yPix,
                  double tolerancePix) {
  const std::vector<std::string> tiles = table.strings("TILE");
  const std::vector<double> xs = table.doubles("X_IMAGE"), ys = table.doubles("Y_IMAGE");
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    if (tiles[i] == tile && std::hypot(xs[i] - xPix, ys[i] - yPix) < tolerancePix) return true;
  }
  return false;
}

TEST_F(BatchRunTest, EveryTileSearchedJournaledAndMergedThenResumed) {
  // Run 1: A and B searched, C (not FITS) failed; the survey is A and B.
  const BatchReport first = runBatch(settings_, cluster_, {});
  ASSERT_EQ(first.tiles.size(), 3u);
  EXPECT_EQ(first.run, 1);
  EXPECT_EQ(states(first), (std::vector<std::string>{"done", "done", "failed"}));
  // A: the arc and the shared bar; B: the shared bar and its own.
  EXPECT_EQ(first.reports[0].candidates, 2);
  EXPECT_EQ(first.reports[1].candidates, 2);
  EXPECT_NE(first.reports[2].message.find((dir_ / "images/C.fits").string()), std::string::npos)
      << first.reports[2].message;
  EXPECT_EQ(first.failed(), 1);
  EXPECT_EQ(journalEvents(1),
            (std::set<std::pair<std::string, std::string>>{
                {"start", "-"}, {"done", "A"}, {"done", "B"}, {"failed", "C"}, {"finished", "-"}}));

  // The shared bar once: B's copy, 39.5 px from B's centre (1-based x 80.5) against A's 60.5.
  ASSERT_TRUE(first.merged);
  const SurveyCandidates& survey = first.survey;
  EXPECT_EQ(survey.tileCandidates, 4);
  EXPECT_EQ(survey.duplicatesRemoved, 1);
  ASSERT_EQ(survey.table.rows(), 3);
  EXPECT_TRUE(hasCandidate(survey.table, "A", arcCentroidX() + 1, kLensY + 1, 0.3));
  EXPECT_TRUE(
      hasCandidate(survey.table, "B", kSharedBarX - kTileBOffsetPix + 1, kSharedBarY + 1, 0.1));
  EXPECT_TRUE(hasCandidate(survey.table, "B", kBarBX - kTileBOffsetPix + 1, kBarBY + 1, 0.1));
  EXPECT_EQ(survey.keptPerTile, (std::vector<std::int64_t>{1, 2, 0}));
  // The union of A and B: the field's 260 x 120 pixels, not 2 x 160 x 120.
  EXPECT_NEAR(survey.areaDeg2 / (double(kFieldWidthPix * kHeightPix) * kPixelDeg2), 1.0, 1e-4);
  ASSERT_EQ(survey.spaces.size(), 1u);
  EXPECT_EQ(survey.spaces[0].candidates, 1);  // the arc

  EXPECT_EQ(test::fileNames(out()),
            (std::set<std::string>{kBatchMarkerFile, "journal.txt", "configuration.txt", "claims",
                                   "tiles", "candidates.fits", "summary.txt", "index.html",
                                   "candidates.html", "candidates.reg", "candidates.cat"}));
  EXPECT_EQ(test::fileNames(out() / "tiles"), (std::set<std::string>{"A", "B"}));
  // A claim file for each tile searched, each free again once the run is over.
  EXPECT_EQ(test::fileNames(out() / "claims"), (std::set<std::string>{"A", "B", "C"}));
  for (const char* tile : {"A", "B", "C"}) {
    EXPECT_TRUE(TileClaim::tryTake((out() / "claims" / tile).string()).has_value()) << tile;
  }
  for (const char* tile : {"A", "B"}) {
    const std::set<std::string> files = test::fileNames(out() / "tiles" / tile);
    for (const char* name : {kSearchMarkerFile, "area.fits", "candidates.fits", "summary.txt"}) {
      EXPECT_EQ(files.count(name), 1u) << tile << "/" << name;
    }
  }
  const FitsTable written = readFitsTable((out() / "candidates.fits").string(), "LDAC_OBJECTS");
  EXPECT_EQ(written.rows(), 3);
  // One region per survey candidate, and the vetting page's tile filter has tiles to offer.
  const std::string regions = test::readFile(out() / "candidates.reg");
  std::size_t circles = 0;
  for (std::size_t at = regions.find("\ncircle("); at != std::string::npos;
       at = regions.find("\ncircle(", at + 1)) {
    ++circles;
  }
  EXPECT_EQ(circles, 3u);
  EXPECT_NE(test::readFile(out() / "candidates.html").find("\"tiles\":true"), std::string::npos);
  EXPECT_EQ(written.integer("NDUPLIC"), 1);
  std::string summary;
  for (const std::string& line : first.summaryLines) summary += line + "\n";
  EXPECT_EQ(test::readFile(out() / "summary.txt"), summary);
  EXPECT_NE(summary.find("\nRun 1 (1 rank(s), whole manifest): 2 done, 1 failed, 0 skipped "
                         "(done earlier or by other runs)\n"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("  failed: C (line 4): "), std::string::npos) << summary;
  EXPECT_NE(summary.find("\n3 candidate(s), "), std::string::npos) << summary;
  EXPECT_NE(summary.find("; 4 in the tiles, 1 duplicate(s) in overlaps removed\n"),
            std::string::npos)
      << summary;

  // Run 2, C readable now: only C is searched. A's folder is not written again (a file put in
  // it stays: a search replaces the folder whole).
  writeTileC(dir_ / "images/C.fits");
  test::writeTextFile(out() / "tiles/A/kept.txt", "A was searched once\n");
  const BatchReport second = runBatch(settings_, cluster_, {});
  EXPECT_EQ(second.run, 2);
  EXPECT_EQ(states(second), (std::vector<std::string>{"done earlier", "done earlier", "done"}));
  EXPECT_EQ(second.reports[2].candidates, 1);
  EXPECT_EQ(journalEvents(2), (std::set<std::pair<std::string, std::string>>{
                                  {"start", "-"}, {"done", "C"}, {"finished", "-"}}));
  EXPECT_TRUE(fs::exists(out() / "tiles/A/kept.txt"));
  ASSERT_TRUE(second.merged);
  EXPECT_EQ(second.survey.tileCandidates, 5);
  EXPECT_EQ(second.survey.duplicatesRemoved, 1);
  ASSERT_EQ(second.survey.table.rows(), 4);
  EXPECT_TRUE(hasCandidate(second.survey.table, "C", kBarCX + 1, kBarCY + 1, 0.1));
  EXPECT_EQ(second.survey.keptPerTile, (std::vector<std::int64_t>{1, 2, 1}));
  const double unionPix = double(kFieldWidthPix * kHeightPix + kTileCSidePix * kTileCSidePix);
  EXPECT_NEAR(second.survey.areaDeg2 / (unionPix * kPixelDeg2), 1.0, 1e-4);
  EXPECT_EQ(readFitsTable((out() / "candidates.fits").string(), "LDAC_OBJECTS").rows(), 4);

  // Run 3: nothing left to search; the survey is merged again from the tiles' folders.
  const BatchReport third = runBatch(settings_, cluster_, {});
  EXPECT_EQ(third.run, 3);
  EXPECT_EQ(states(third), std::vector<std::string>(3, "done earlier"));
  EXPECT_EQ(journalEvents(3),
            (std::set<std::pair<std::string, std::string>>{{"start", "-"}, {"finished", "-"}}));
  EXPECT_TRUE(third.merged);
  EXPECT_EQ(third.survey.table.rows(), 4);
}

// A manifest, mask or OUTPUT_DIR that cannot be used stops the run before any tile is searched:
// OUTPUT_DIR is not made, or is left as it was.
TEST_F(BatchRunTest, BadManifestOrOutputDirectoryThrowsBeforeAnyTileIsSearched) {
  BatchSettings missingImage = settings_;
  missingImage.manifest =
      test::writeTextFile(dir_ / "missing.txt", "images/A.fits\nimages/D.fits\n");
  test::expectError<ConfigError>([&] { runBatch(missingImage, cluster_, {}); },
                                 {missingImage.manifest + ":2:"});
  EXPECT_FALSE(fs::exists(out()));

  // A's mask is no region file: found while planning, A's image being good.
  test::writeTextFile(dir_ / "images/A.reg", "circle(10,10\n");
  BatchSettings badMask = settings_;
  badMask.manifest = test::writeTextFile(dir_ / "masked.txt", "images/A.fits - images/A.reg\n");
  test::expectError<ConfigError>([&] { runBatch(badMask, cluster_, {}); },
                                 {badMask.manifest + ":1:", "images/A.reg"});
  EXPECT_FALSE(fs::exists(out()));

  // A directory of the user's, not a batch's.
  fs::create_directories(out());
  test::writeTextFile(out() / "notes.txt", "my notes\n");
  test::expectError<ConfigError>([&] { runBatch(settings_, cluster_, {}); },
                                 {"OUTPUT_DIR " + settings_.outputDir, kBatchMarkerFile});
  EXPECT_EQ(test::fileNames(out()), (std::set<std::string>{"notes.txt"}));

  // A file.
  BatchSettings onAFile = settings_;
  onAFile.outputDir = (dir_ / "survey.txt").string();
  test::expectError<ConfigError>([&] { runBatch(onAFile, cluster_, {}); },
                                 {onAFile.outputDir, "not a directory"});
}

}  // namespace
}  // namespace octarc
