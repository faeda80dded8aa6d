#include "octarc/batch/Manifest.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "ExpectError.h"
#include "TestFiles.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;
using test::writeTextFile;

class ManifestTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("octarc-manifest-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "tiles");
    for (const char* f : {"tiles/a.fits", "tiles/a.weight.fits", "tiles/b.fits.fz", "tiles/c.fit",
                          "tiles/a.reg", "tiles/a.ldac", "other.fits"}) {
      writeTextFile(dir_ / f, "x");
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string manifest(const std::string& text) { return writeTextFile(dir_ / "survey.txt", text); }
  fs::path dir_;
};

TEST_F(ManifestTest, CsvWithHeaderCommentsAndEmptyFields) {
  const std::string m = manifest(
      "image,weight,mask,catalog\n"
      "# the first tile\n"
      "tiles/a.fits, tiles/a.weight.fits, tiles/a.reg, tiles/a.ldac\n"
      "\n"
      "tiles/b.fits.fz,-,,\n");
  const std::vector<Tile> tiles = readManifest(m);
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].name, "a");
  EXPECT_EQ(tiles[0].line, 3);
  // Relative paths are taken from the manifest's folder.
  EXPECT_EQ(tiles[0].imagePath, (dir_ / "tiles/a.fits").string());
  EXPECT_EQ(tiles[0].weightPath, (dir_ / "tiles/a.weight.fits").string());
  EXPECT_EQ(tiles[0].maskPath, (dir_ / "tiles/a.reg").string());
  EXPECT_EQ(tiles[0].catalogPath, (dir_ / "tiles/a.ldac").string());
  EXPECT_EQ(tiles[1].name, "b");  // .fits.fz stripped
  EXPECT_EQ(tiles[1].line, 5);
  EXPECT_EQ(tiles[1].weightPath, "");
  EXPECT_EQ(tiles[1].maskPath, "");
}

TEST_F(ManifestTest, BlankSeparatedFieldsAndAbsolutePaths) {
  const std::string abs = (dir_ / "other.fits").string();
  const std::vector<Tile> tiles = readManifest(manifest("tiles/c.fit\t- \n" + abs + "\n"));
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].name, "c");
  EXPECT_EQ(tiles[1].imagePath, abs);
  EXPECT_EQ(tiles[1].name, "other");
}

TEST_F(ManifestTest, GlobOfImagesInSortedOrderWithoutTheWeightMaps) {
  const std::vector<Tile> tiles = readManifest((dir_ / "tiles" / "*.fit*").string());
  ASSERT_EQ(tiles.size(), 3u);  // a.fits, b.fits.fz, c.fit; a.weight.fits is a's weight map
  EXPECT_EQ(tiles[0].name, "a");
  EXPECT_EQ(tiles[1].name, "b");
  EXPECT_EQ(tiles[2].name, "c");
  EXPECT_EQ(tiles[0].line, 0);
  EXPECT_EQ(tiles[0].weightPath, "");  // no weights asked for
  test::expectError<ConfigError>([&] { readManifest((dir_ / "none" / "*.fits").string()); },
                                 {"no file matches"});
  test::expectError<ConfigError>([&] { readManifest((dir_ / "tiles" / "*.weight.*").string()); },
                                 {"*.weight.*: only weight maps", "no image"});
}

TEST_F(ManifestTest, GlobPairsEachImageWithTheWeightMapBesideIt) {
  fs::create_directories(dir_ / "sim");
  for (const char* f : {"sim/f1.fits", "sim/f1.weight.fits", "sim/f2.fits", "sim/f2.weight.fits"}) {
    writeTextFile(dir_ / f, "x");
  }
  const std::vector<Tile> tiles = readManifest((dir_ / "sim" / "*.fits").string(), true);
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].imagePath, (dir_ / "sim/f1.fits").string());
  EXPECT_EQ(tiles[0].weightPath, (dir_ / "sim/f1.weight.fits").string());
  EXPECT_EQ(tiles[1].imagePath, (dir_ / "sim/f2.fits").string());
  EXPECT_EQ(tiles[1].weightPath, (dir_ / "sim/f2.weight.fits").string());
  // b.fits.fz and c.fit have none.
  test::expectError<ConfigError>(
      [&] { readManifest((dir_ / "tiles" / "*.fit*").string(), true); },
      {(dir_ / "tiles/b.fits.fz").string(), "has no weight map", "b.weight.fits"});
}

// RFC 4180 quoting: a quoted field holds commas, blanks, '#' and "" for a quote; a comment is a
// line of its own.
TEST_F(ManifestTest, QuotedPathsWithBlanksCommasHashesAndQuotes) {
  for (const char* f : {"tiles/a b.fits", "tiles/c,d.fits", "tiles/e#1.fits",
                        "tiles/say \"hi\".fits", "tiles/w, 1.fits"}) {
    writeTextFile(dir_ / f, "x");
  }
  const std::vector<Tile> tiles =
      readManifest(manifest("image,weight\n"
                            "\"tiles/a b.fits\", \"tiles/w, 1.fits\"\n"
                            "  # a comment, with \"an open quote\n"
                            "\"tiles/c,d.fits\",-\n"
                            "tiles/e#1.fits\n"
                            "\"tiles/say \"\"hi\"\".fits\"   \"tiles/a.reg\"\n"));
  ASSERT_EQ(tiles.size(), 4u);
  EXPECT_EQ(tiles[0].imagePath, (dir_ / "tiles/a b.fits").string());
  EXPECT_EQ(tiles[0].weightPath, (dir_ / "tiles/w, 1.fits").string());
  EXPECT_EQ(tiles[0].name, "a b");
  EXPECT_EQ(tiles[1].imagePath, (dir_ / "tiles/c,d.fits").string());
  EXPECT_EQ(tiles[1].line, 4);
  EXPECT_EQ(tiles[1].weightPath, "");
  EXPECT_EQ(tiles[2].imagePath, (dir_ / "tiles/e#1.fits").string());
  // Blank-separated, quoted.
  EXPECT_EQ(tiles[3].imagePath, (dir_ / "tiles/say \"hi\".fits").string());
  EXPECT_EQ(tiles[3].weightPath, (dir_ / "tiles/a.reg").string());
}

TEST_F(ManifestTest, BadQuotesAreNamedByLine) {
  test::expectError<ConfigError>(
      [&] { readManifest(manifest("tiles/a.fits\n\"tiles/a b.fits\n")); },
      {"survey.txt:2: ", "a quote (\") is not closed"});
  test::expectError<ConfigError>([&] { readManifest(manifest("\"tiles/a\".fits,-\n")); },
                                 {"survey.txt:1: ", "text after a closing quote"});
  test::expectError<ConfigError>([&] { readManifest(manifest("tiles/a\"\"b.fits\n")); },
                                 {"survey.txt:1: ", "a quote inside a field"});
}

TEST_F(ManifestTest, BadLinesAreNamedByLine) {
  test::expectError<ConfigError>(
      [&] { readManifest(manifest("tiles/a.fits\ntiles/a.fits,tiles/missing.fits\n")); },
      {"survey.txt:2: ", "weight map", "missing.fits", "no such file"});
  test::expectError<ConfigError>(
      [&] { readManifest(manifest("tiles/a.fits\n# c\ntiles/./a.fits\n")); },
      {"survey.txt:3: ", "duplicate tile", "line 1"});
  fs::create_directories(dir_ / "b");
  writeTextFile(dir_ / "b" / "a.fits", "x");
  test::expectError<ConfigError>([&] { readManifest(manifest("tiles/a.fits\nb/a.fits\n")); },
                                 {"survey.txt:2: ", "duplicate tile name a", "line 1"});
  test::expectError<ConfigError>([&] { readManifest(manifest("tiles/a.fits,-,-,-,extra\n")); },
                                 {"survey.txt:1: ", "too many fields (5)"});
  // A mask that is a folder cannot be read.
  test::expectError<ConfigError>([&] { readManifest(manifest("tiles/a.fits,-,tiles\n")); },
                                 {"survey.txt:1: ", "mask", "cannot be read"});
  test::expectError<ConfigError>([&] { readManifest(manifest("# nothing\n\n")); },
                                 {"survey.txt", "lists no tile"});
  test::expectError<ConfigError>([&] { readManifest(manifest("image,weight\n")); },
                                 {"lists no tile"});
  test::expectIoError([&] { readManifest((dir_ / "absent.txt").string()); },
                      {"absent.txt", "cannot read the manifest"});
}

// TASK MEASURE: IMAGE SEGMENTATION CATALOG [WEIGHT], quoted as in CSV, the header's first field
// "image" too.
TEST_F(ManifestTest, MeasureRowsOfThreeOrFourFields) {
  writeTextFile(dir_ / "tiles/a seg.fits", "x");
  const std::vector<Tile> tiles = readManifest(
      manifest("image,segmentation,catalog,weight\n"
               "tiles/a.fits, \"tiles/a seg.fits\", tiles/a.ldac, tiles/a.weight.fits\n"
               "# the second\n"
               "tiles/c.fit tiles/a.reg tiles/a.ldac\n"),
      false, ManifestRows::Measure);
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].name, "a");
  EXPECT_EQ(tiles[0].line, 2);
  EXPECT_EQ(tiles[0].imagePath, (dir_ / "tiles/a.fits").string());
  EXPECT_EQ(tiles[0].segmentationPath, (dir_ / "tiles/a seg.fits").string());
  EXPECT_EQ(tiles[0].catalogPath, (dir_ / "tiles/a.ldac").string());
  EXPECT_EQ(tiles[0].weightPath, (dir_ / "tiles/a.weight.fits").string());
  EXPECT_EQ(tiles[0].maskPath, "");
  EXPECT_EQ(tiles[1].name, "c");
  EXPECT_EQ(tiles[1].line, 4);
  EXPECT_EQ(tiles[1].segmentationPath, (dir_ / "tiles/a.reg").string());
  EXPECT_EQ(tiles[1].weightPath, "");
  // The same rows as a search's: image, weight, mask.
  const std::vector<Tile> searched =
      readManifest(manifest("tiles/c.fit tiles/a.reg tiles/a.ldac\n"));
  EXPECT_EQ(searched[0].segmentationPath, "");
  EXPECT_EQ(searched[0].weightPath, (dir_ / "tiles/a.reg").string());
}

TEST_F(ManifestTest, BadMeasureRowsAreNamedByLine) {
  const auto measure = [&](const std::string& text) {
    readManifest(manifest(text), false, ManifestRows::Measure);
  };
  test::expectError<ConfigError>(
      [&] { measure("tiles/a.fits,tiles/a.reg,tiles/a.ldac\ntiles/c.fit,tiles/a.reg\n"); },
      {"survey.txt:2: ", "2 field(s)", "IMAGE SEGMENTATION CATALOG [WEIGHT]"});
  test::expectError<ConfigError>([&] { measure("tiles/a.fits\n"); },
                                 {"survey.txt:1: ", "1 field(s)"});
  test::expectError<ConfigError>([&] { measure("tiles/a.fits,tiles/a.reg,tiles/a.ldac,-,x\n"); },
                                 {"survey.txt:1: ", "5 field(s)"});
  test::expectError<ConfigError>([&] { measure("tiles/a.fits,-,tiles/a.ldac\n"); },
                                 {"survey.txt:1: ", "no segmentation image"});
  test::expectError<ConfigError>([&] { measure("tiles/a.fits,tiles/a.reg,\n"); },
                                 {"survey.txt:1: ", "no catalog"});
  test::expectError<ConfigError>(
      [&] { measure("# x\ntiles/a.fits,tiles/missing.fits,tiles/a.ldac\n"); },
      {"survey.txt:2: ", "segmentation image", "missing.fits", "no such file"});
  test::expectError<ConfigError>(
      [&] { readManifest((dir_ / "tiles" / "*.fits").string(), false, ManifestRows::Measure); },
      {"not a glob"});
}

}  // namespace
}  // namespace octarc
