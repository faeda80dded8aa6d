#include "octarc/core/AtomicFile.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

TEST(AtomicFile, CommitReplacesTargetAndAbandonLeavesItUntouched) {
  auto dir = test::scratchDir();
  auto target = dir / "out.cat";
  std::ofstream(target) << "old";
  {
    AtomicFile f(target.string());
    std::ofstream(f.tempPath()) << "half-written";
    // no commit: as if the run failed
  }
  EXPECT_EQ(test::readFile(target), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  {
    AtomicFile f(target.string());
    std::ofstream(f.tempPath()) << "new";
    f.commit();
  }
  EXPECT_EQ(test::readFile(target), "new");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
}

std::vector<std::string> entries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(OutputFiles, NothingAppearsUntilCommitThenEverything) {
  auto dir = test::scratchDir();
  std::ofstream(dir / "cat.ldac") << "old catalog";
  std::ofstream(dir / "seg.fits") << "old image";
  {
    OutputFiles out;
    out.add((dir / "cat.ldac").string());
    out.add((dir / "seg.fits").string());
    out.write(0, [](const std::string& p) { std::ofstream(p) << "new catalog"; });
    out.write(1, [](const std::string& p) { std::ofstream(p) << "new image"; });
    // Both written, not committed (a failure, or an exception, from here on): the old set.
  }
  EXPECT_EQ(test::readFile(dir / "cat.ldac"), "old catalog");
  EXPECT_EQ(test::readFile(dir / "seg.fits"), "old image");
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"cat.ldac", "seg.fits"}));
  OutputFiles out;
  out.add((dir / "cat.ldac").string());
  out.add((dir / "seg.fits").string());
  out.write(0, [](const std::string& p) { std::ofstream(p) << "new catalog"; });
  // The second output was never written: commit refuses, the old set stays.
  EXPECT_THROW(out.commit(), IoError);
  EXPECT_EQ(test::readFile(dir / "cat.ldac"), "old catalog");
  out.write(1, [](const std::string& p) { std::ofstream(p) << "new image"; });
  out.commit();
  EXPECT_EQ(test::readFile(dir / "cat.ldac"), "new catalog");
  EXPECT_EQ(test::readFile(dir / "seg.fits"), "new image");
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"cat.ldac", "seg.fits"}));
}

TEST(OutputFiles, ErrorsNameTheFinalFileNotTheTemporary) {
  auto dir = test::scratchDir();
  OutputFiles out;
  const AtomicFile& f = out.add((dir / "cat.ldac").string());
  try {
    out.write(0, [](const std::string& p) { throw IoError(p + ": cannot write (disk full)"); });
    FAIL() << "no exception";
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()), f.finalPath() + ": cannot write (disk full)");
  }
}

TEST(OutputFiles, RefusesBadNamesBeforeAnyWork) {
  auto dir = test::scratchDir();
  OutputFiles out;
  out.add((dir / "a.fits").string());
  EXPECT_THROW(out.add((dir / "./a.fits").string()), ConfigError);   // twice
  EXPECT_THROW(out.add((dir / "no" / "b.fits").string()), IoError);  // no directory
  EXPECT_THROW(out.add(dir.string()), IoError);                      // a directory
  EXPECT_THROW(out.add(""), ConfigError);
}

TEST(RefuseOutputOverInput, SameFileByNameOrLink) {
  auto dir = test::scratchDir();
  std::ofstream(dir / "in.fits") << "x";
  std::filesystem::create_symlink(dir / "in.fits", dir / "link.fits");
  const std::string in = (dir / "in.fits").string();
  EXPECT_THROW(refuseOutputOverInput(in, "CATALOG_NAME", in, "image"), ConfigError);
  EXPECT_THROW(refuseOutputOverInput((dir / "link.fits").string(), "CATALOG_NAME", in, "image"),
               ConfigError);
  EXPECT_THROW(
      refuseOutputOverInput((dir / "in.fits").string(), "CATALOG_NAME", in + "[1]", "image"),
      ConfigError);
  EXPECT_NO_THROW(refuseOutputOverInput((dir / "out.fits").string(), "CATALOG_NAME", in, "image"));
  try {
    refuseOutputOverInput(in, "CATALOG_NAME", in, "INPUT_CATALOG");
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("CATALOG_NAME"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("INPUT_CATALOG"), std::string::npos);
  }
}

TEST(AtomicFile, RemovesTemporariesOfDeadProcessesOnly) {
  auto dir = test::scratchDir();
  // A pid that exists (ours) and one that cannot (beyond pid_max on Linux, 2^22).
  const std::string dead = "99999999", alive = std::to_string(::getpid());
  for (const std::string& name :
       {".out.cat.tmp." + dead + ".0", "..out.cat.tmp." + dead + ".3.tmp." + dead + ".4",
        ".out.cat.tmp." + alive + ".7", ".other.cat.tmp." + dead + ".0",
        std::string(".out.cat.tmp.x.1")}) {
    std::ofstream(dir / name) << "left by a killed run";
  }
  { AtomicFile f((dir / "out.cat").string()); }
  EXPECT_EQ(entries(dir),
            (std::vector<std::string>{".other.cat.tmp." + dead + ".0",
                                      ".out.cat.tmp." + alive + ".7", ".out.cat.tmp.x.1"}));
}

}  // namespace
}  // namespace octarc
