#include "octarc/core/DataFiles.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

// Sets (or unsets, with nullopt) OCTARC_DATA_DIR for the life of the object.
class DataDirOverride {
 public:
  explicit DataDirOverride(std::optional<std::string> value) {
    if (const char* old = std::getenv("OCTARC_DATA_DIR")) old_ = old;
    if (value) {
      setenv("OCTARC_DATA_DIR", value->c_str(), 1);
    } else {
      unsetenv("OCTARC_DATA_DIR");
    }
  }
  ~DataDirOverride() {
    if (old_) {
      setenv("OCTARC_DATA_DIR", old_->c_str(), 1);
    } else {
      unsetenv("OCTARC_DATA_DIR");
    }
  }

 private:
  std::optional<std::string> old_;
};

TEST(DataFiles, EnvironmentNamesTheDataDirectory) {
  const fs::path dir = test::scratchDir();
  fs::create_directories(dir / "simulation");
  std::ofstream(dir / "octarc.sex") << "DETECT_THRESH 3\n";
  std::ofstream(dir / "simulation" / "population.txt") << "#\n";
  const DataDirOverride env(dir.string());
  EXPECT_EQ(dataDirectory(), dir.string());
  EXPECT_EQ(dataFile("octarc.sex"), (dir / "octarc.sex").string());
  EXPECT_EQ(dataFile("simulation/population.txt"),
            (dir / "simulation" / "population.txt").string());
  try {
    dataFile("octarc.param");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find((dir / "octarc.param").string()), std::string::npos) << what;
    EXPECT_NE(what.find("OCTARC_DATA_DIR"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // A directory of that name is not the file.
  fs::create_directories(dir / "default.conv");
  EXPECT_THROW(dataFile("default.conv"), IoError);
}

TEST(DataFiles, WithoutEnvironmentTheDirectoryIsBesideTheExecutable) {
  const DataDirOverride env(std::nullopt);
  // This test program is not installed: no share/octarc beside it.
  const fs::path expected =
      (fs::path(OCTARC_TEST_EXE_DIR) / OCTARC_DATA_DIR_FROM_BINDIR).lexically_normal();
  EXPECT_EQ(fs::path(dataDirectory()), expected);
  try {
    dataFile("octarc.sex");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find((expected / "octarc.sex").string()), std::string::npos) << what;
    EXPECT_NE(what.find("beside the octarc executable"), std::string::npos) << what;
  }
}

TEST(DataFiles, AnEmbeddingProgramNamesTheDirectoryUnlessTheEnvironmentDoes) {
  const fs::path dir = test::scratchDir();
  std::ofstream(dir / "octarc.sex") << "DETECT_THRESH 3\n";
  const fs::path beside =
      (fs::path(OCTARC_TEST_EXE_DIR) / OCTARC_DATA_DIR_FROM_BINDIR).lexically_normal();
  {
    const DataDirOverride env(std::nullopt);
    setDataDirectory(dir.string());
    EXPECT_EQ(dataDirectory(), dir.string());
    EXPECT_EQ(dataFile("octarc.sex"), (dir / "octarc.sex").string());
    {
      const DataDirOverride other("/elsewhere");
      EXPECT_EQ(dataDirectory(), "/elsewhere");
    }
    setDataDirectory("");
    EXPECT_EQ(fs::path(dataDirectory()), beside);
  }
}

TEST(DataFiles, UserFilesComeFirstThenShippedOnes) {
  const fs::path data = test::scratchDir() / "share";
  const fs::path work = data.parent_path() / "work";
  fs::create_directories(data);
  fs::create_directories(work);
  std::ofstream(data / "default.conv") << "CONV NORM\n1\n";
  std::ofstream(data / "octarc.param") << "NUMBER\n";
  std::ofstream(work / "octarc.param") << "NUMBER\nX_IMAGE\n";
  const DataDirOverride env(data.string());
  // Back to the first working directory however the test ends.
  struct RestoreWorkingDirectory {
    fs::path path = fs::current_path();
    ~RestoreWorkingDirectory() { fs::current_path(path); }
  } restoreWorkingDirectory;
  fs::current_path(work);
  // In the working directory: the user's own file.
  EXPECT_EQ(userOrDataFile("octarc.param"), "octarc.param");
  // Not there, no directory given: the shipped file.
  EXPECT_EQ(userOrDataFile("default.conv"), (data / "default.conv").string());
  // With a directory the name is the user's, found or not; unknown names stay as given.
  EXPECT_EQ(userOrDataFile("./default.conv"), "./default.conv");
  EXPECT_EQ(userOrDataFile("sub/default.conv"), "sub/default.conv");
  EXPECT_EQ(userOrDataFile("missing.param"), "missing.param");
}

}  // namespace
}  // namespace octarc
