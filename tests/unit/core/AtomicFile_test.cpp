#include "octarc/core/AtomicFile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "TestPaths.h"

namespace octarc {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AtomicFile, CommitReplacesTargetAndAbandonLeavesItUntouched) {
  auto dir = test::scratchDir();
  auto target = dir / "out.cat";
  std::ofstream(target) << "old";
  {
    AtomicFile f(target.string());
    std::ofstream(f.tempPath()) << "half-written";
    // no commit: as if the run failed
  }
  EXPECT_EQ(slurp(target), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  {
    AtomicFile f(target.string());
    std::ofstream(f.tempPath()) << "new";
    f.commit();
  }
  EXPECT_EQ(slurp(target), "new");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
}

}  // namespace
}  // namespace octarc
