// Paths the tests need: a scratch directory and the shared reference data.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace octarc::test {

// A fresh, empty scratch directory under the build tree, named after the running test.
inline std::filesystem::path scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(OCTARC_BINARY_DIR) / "test-scratch" /
                              (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// True on the continuous-integration machine (the environment variable CI is "true"), which has
// every program and data set the tests use.
inline bool onCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

// Ends the current test (or SetUp) because a program or data set it needs is absent: a skip,
// which GoogleTest lists as SKIPPED, with the streamed reason; on the CI machine a failure,
// since a missing dependency there means a broken installation, not a test to leave out.
// Usage: if (!haveProgram("fitsverify")) OCTARC_SKIP_MISSING() << "fitsverify not installed";
// (TestCommands.h has the program checks.)
#define OCTARC_SKIP_MISSING()                                                     \
  return ::testing::internal::AssertHelper(                                       \
             ::octarc::test::onCi() ? ::testing::TestPartResult::kFatalFailure    \
                                    : ::testing::TestPartResult::kSkip,           \
             __FILE__, __LINE__,                                                  \
             ::octarc::test::onCi()                                               \
                 ? "CI=true: a missing dependency is a failure on the CI machine" \
                 : "") = ::testing::Message()

// The shared reference data directory (real survey images and SExtractor outputs that the
// project does not ship): $OCTARC_SHARED_DIR, else ../shared next to the source tree. Empty
// if absent; tests then end with OCTARC_SKIP_MISSING() and a message.
inline std::filesystem::path sharedDataDir() {
  if (const char* env = std::getenv("OCTARC_SHARED_DIR")) {
    std::filesystem::path p(env);
    if (std::filesystem::exists(p / "data" / "real")) return p / "data" / "real";
  }
  std::filesystem::path p = std::filesystem::path(OCTARC_SOURCE_DIR).parent_path() / "shared";
  if (std::filesystem::exists(p / "data" / "real")) return p / "data" / "real";
  return {};
}

#define OCTARC_REQUIRE_SHARED_DATA(dir)                                              \
  const std::filesystem::path dir = ::octarc::test::sharedDataDir();                 \
  if (dir.empty())                                                                   \
  OCTARC_SKIP_MISSING() << "shared reference data (../shared/data/real) not found; " \
                           "set OCTARC_SHARED_DIR to run this test"

}  // namespace octarc::test
