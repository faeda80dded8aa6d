// Where a FILTER_NAME is looked for (README, Usage): the name as given when it exists or has a
// directory, else params/ of the source tree, else /usr/share/source-extractor/, else an error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ExpectError.h"
#include "TestPaths.h"
#include "octarc/run/PreparedImage.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

// Runs the test body in a fresh working directory, and goes back afterwards.
class FilterLookup : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = fs::current_path();
    dir_ = test::scratchDir();
    fs::current_path(dir_);
  }
  void TearDown() override { fs::current_path(previous_); }
  fs::path previous_, dir_;
};

TEST_F(FilterLookup, ParamsDirectoryComesBeforeSExtractorsShare) {
  // default.conv is in both; params/ wins.
  const fs::path found = resolveFilterFile("default.conv");
  EXPECT_TRUE(fs::equivalent(found, fs::path(OCTARC_SOURCE_DIR) / "params" / "default.conv"))
      << found;
}

TEST_F(FilterLookup, NamesOnlyInSExtractorsShareAreFoundThere) {
  const fs::path share = "/usr/share/source-extractor/gauss_2.0_5x5.conv";
  if (!fs::exists(share)) OCTARC_SKIP_MISSING() << share << " not installed (source-extractor)";
  ASSERT_FALSE(fs::exists(fs::path(OCTARC_SOURCE_DIR) / "params" / "gauss_2.0_5x5.conv"));
  EXPECT_EQ(fs::path(resolveFilterFile("gauss_2.0_5x5.conv")), share);
}

TEST_F(FilterLookup, TheWorkingDirectoryComesFirst) {
  std::ofstream("default.conv") << "CONV NORM\n0 0 0\n0 1 0\n0 0 0\n";
  EXPECT_EQ(resolveFilterFile("default.conv"), "default.conv");
}

TEST_F(FilterLookup, NamesWithADirectoryAreKeptAsGiven) {
  EXPECT_EQ(resolveFilterFile("sub/gauss_2.0_5x5.conv"), "sub/gauss_2.0_5x5.conv");
}

// A name found nowhere is an error naming it and every place searched.
TEST_F(FilterLookup, NamesFoundNowhereAreAnErrorNamingThePlaces) {
  test::expectIoError(
      [] { (void)resolveFilterFile("no-such-mask.conv"); },
      {"no-such-mask.conv", "FILTER_NAME", "working directory",
       (fs::path(OCTARC_SOURCE_DIR) / "params").string(), "/usr/share/source-extractor"});
}

}  // namespace
}  // namespace octarc
