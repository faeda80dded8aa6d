#include "octarc/core/Interrupt.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "TestFiles.h"
#include "TestPaths.h"
#include "octarc/core/AtomicFile.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

// Runs `body` in a child process and returns its exit status (or -signal).
template <typename Fn>
int inChild(Fn body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    body();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

TEST(Interrupt, SignalRemovesTemporariesAndRegisteredPathsAndExits128PlusSignal) {
  const fs::path dir = test::scratchDir();
  const fs::path made = dir / "made";
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const int status = inChild([&] {
      installInterruptCleanup("test");
      fs::create_directory(made);
      removeOnInterrupt(made.string(), true);
      AtomicFile f((made / "out.fits").string());
      std::ofstream(f.tempPath()) << "half";
      const fs::path provisional = made / "step1.fits";
      std::ofstream(provisional) << "done, but the run is not";
      removeOnInterrupt(provisional.string());
      ::raise(sig);
      ::_exit(99);  // not reached
    });
    EXPECT_EQ(status, 128 + sig);
    EXPECT_FALSE(fs::exists(made)) << "signal " << sig;
  }
}

TEST(Interrupt, HeldBackDuringRenamesThenTheRunEndsWithItsOutputs) {
  const fs::path dir = test::scratchDir();
  const int status = inChild([&] {
    installInterruptCleanup("test");
    OutputFiles out;
    out.add((dir / "a.txt").string());
    out.write(0, [](const std::string& p) { std::ofstream(p) << "a"; });
    {
      DeferInterrupts hold;
      ::raise(SIGTERM);  // waits
      out.commit();
    }
    ::_exit(99);  // not reached: the held-back signal ends the process here
  });
  EXPECT_EQ(status, 128 + SIGTERM);
  EXPECT_TRUE(fs::exists(dir / "a.txt"));
}

TEST(Interrupt, AfterTheOutputsAreInPlaceTheLineSaysTheyAreComplete) {
  const fs::path dir = test::scratchDir();
  const fs::path log = dir / "stderr.txt";
  const int status = inChild([&] {
    std::freopen(log.c_str(), "w", stderr);
    installInterruptCleanup("test");
    OutputFiles out;
    out.add((dir / "cat.ldac").string());
    out.write(0, [](const std::string& p) { std::ofstream(p) << "catalog"; });
    out.commit();
    ::raise(SIGINT);
  });
  EXPECT_EQ(status, 130);
  EXPECT_TRUE(fs::exists(dir / "cat.ldac"));
  EXPECT_EQ(test::readFile(log),
            "test: interrupted by SIGINT after its outputs were written; they are "
            "complete\n");
}

// A run kept piece by piece: the line counts the pieces, and says whether the final outputs are
// in place: not while only pieces (here one, committed as outputs of their own) are; yes once
// those after markNextOutputsFinal are, also when the signal waited for their renames.
TEST(Interrupt, APiecesAccountCountsThePiecesAndSaysWhetherTheFinalOutputsAreWritten) {
  const fs::path dir = test::scratchDir();
  const PiecesAccount account{": ", " kept; ", "final written", "no final output"};
  for (const bool final : {false, true}) {
    const fs::path log = dir / "stderr.txt";
    const int status = inChild([&] {
      std::freopen(log.c_str(), "w", stderr);
      installInterruptCleanup("test");
      accountPiecesOnInterrupt(account);
      OutputFiles piece;
      piece.add((dir / "piece.txt").string());
      piece.write(0, [](const std::string& p) { std::ofstream(p) << "1"; });
      piece.commit();
      for (int k = 0; k < 12; ++k) notePieceKept();
      if (!final) ::raise(SIGTERM);
      markNextOutputsFinal();
      OutputFiles last;
      last.add((dir / "final.txt").string());
      last.write(0, [](const std::string& p) { std::ofstream(p) << "2"; });
      const DeferInterrupts hold;
      ::raise(SIGTERM);
      last.commit();
    });
    EXPECT_EQ(status, 128 + SIGTERM);
    EXPECT_EQ(fs::exists(dir / "final.txt"), final);
    EXPECT_EQ(test::readFile(log), std::string("test: interrupted by SIGTERM: 12 kept; ") +
                                       (final ? "final written" : "no final output") + "\n");
  }
}

TEST(Interrupt, ForgottenPathsStay) {
  const fs::path dir = test::scratchDir();
  const int status = inChild([&] {
    installInterruptCleanup("test");
    std::ofstream(dir / "kept.txt") << "kept";
    forgetOnInterrupt(removeOnInterrupt((dir / "kept.txt").string()));
    AtomicFile f((dir / "final.txt").string());
    std::ofstream(f.tempPath()) << "final";
    f.commit();
    ::raise(SIGINT);
  });
  EXPECT_EQ(status, 130);
  EXPECT_TRUE(fs::exists(dir / "kept.txt"));
  EXPECT_TRUE(fs::exists(dir / "final.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 2);
}

}  // namespace
}  // namespace octarc
