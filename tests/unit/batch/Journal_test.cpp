#include "octarc/batch/Journal.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "TestFiles.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const char* name) {
  const fs::path p = fs::temp_directory_path() / (std::string("octarc-journal-") + name);
  fs::remove(p);
  return p;
}

TEST(Journal, RunsAreNumberedAndLinesReadBack) {
  const fs::path path = scratch("runs");
  const Journal journal(path.string());
  EXPECT_TRUE(journal.read().empty());  // no file yet
  EXPECT_EQ(journal.startRun("8 tiles"), 1);
  journal.append(1, "done", "t1", "3 candidates");
  journal.append(1, "failed", "t2", "t2.fits: not a FITS file\twith a tab\nand a line break");
  EXPECT_EQ(journal.startRun("8 tiles"), 2);
  std::vector<JournalEntry> entries;
  journal.appendWhileLocked(2, "done", "t2", "", [&](const std::vector<JournalEntry>& lines) {
    entries = lines;
    // Locked meanwhile: another open description of the file cannot take the lock.
    const int fd = ::open(path.c_str(), O_RDONLY);
    EXPECT_NE(::flock(fd, LOCK_EX | LOCK_NB), 0);
    ::close(fd);
  });
  ASSERT_EQ(entries.size(), 5u);
  EXPECT_EQ(entries[0].event, "start");
  EXPECT_EQ(entries[0].tile, "-");
  EXPECT_EQ(entries[1].run, 1);
  EXPECT_EQ(entries[1].tile, "t1");
  EXPECT_EQ(entries[1].detail, "3 candidates");
  EXPECT_EQ(entries[2].detail, "t2.fits: not a FITS file with a tab and a line break");
  EXPECT_EQ(entries[3].run, 2);
  EXPECT_EQ(entries[4].detail, "-");          // an empty field
  EXPECT_EQ(entries[1].timeUtc.size(), 19u);  // 2026-12-02T18:42:07
  EXPECT_EQ(completedTiles(entries), (std::set<std::string>{"t1", "t2"}));
  fs::remove(path);
}

TEST(Journal, AJournalSetAsideBeforeTheStartIsFollowedByANewOne) {
  const fs::path path = scratch("aside");
  const fs::path aside = scratch("aside.earlier");
  Journal journal(path.string());
  journal.startRun("run 1");
  journal.append(1, "done", "t1", "");
  std::size_t seen = 0;
  EXPECT_EQ(journal.startRun("run 2",
                             [&](const std::vector<JournalEntry>& lines) {
                               seen = lines.size();
                               fs::rename(path, aside);
                               return true;
                             }),
            1);  // the first run of the new journal
  EXPECT_EQ(seen, 2u);
  ASSERT_EQ(journal.read().size(), 1u);
  EXPECT_EQ(journal.read()[0].detail, "run 2");
  EXPECT_EQ(Journal(aside.string()).read().size(), 2u);
  // A check that throws: no start line.
  EXPECT_THROW(journal.startRun("run 3",
                                [](const std::vector<JournalEntry>&) -> bool {
                                  throw ConfigError("another configuration");
                                }),
               ConfigError);
  EXPECT_EQ(journal.read().size(), 1u);
  // The guard runs before each later line; when it throws, the line is not written.
  bool stop = false;
  journal.guardAppends([&] {
    if (stop) throw ConfigError("set aside by another run");
  });
  journal.append(1, "done", "t1", "");
  stop = true;
  EXPECT_THROW(journal.append(1, "done", "t2", ""), ConfigError);
  EXPECT_THROW(
      journal.appendWhileLocked(1, "finished", "-", "", [](const std::vector<JournalEntry>&) {}),
      ConfigError);
  ASSERT_EQ(journal.read().size(), 2u);
  EXPECT_EQ(journal.read()[1].tile, "t1");
  fs::remove(path);
  fs::remove(aside);
}

// A run waiting for the lock while another moves the journal aside (RESTART Y) writes its line
// into the journal the path names afterwards, not into the moved one. The other run holds the
// lock for 200 ms after the waiter has started: long enough for it to be waiting on the file.
TEST(Journal, ALineWaitingWhileTheJournalIsMovedGoesToTheNewOne) {
  const fs::path path = scratch("moved");
  const fs::path aside = scratch("moved.earlier");
  Journal journal(path.string());
  journal.startRun("run 1");
  std::atomic<bool> started{false};
  std::thread waiter;
  journal.appendWhileLocked(1, "done", "t1", "", [&](const std::vector<JournalEntry>&) {
    waiter = std::thread([&] {
      started = true;
      Journal(path.string()).append(2, "done", "t2", "");
    });
    while (!started) std::this_thread::yield();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    fs::rename(path, aside);
  });
  waiter.join();
  const std::vector<JournalEntry> moved = Journal(aside.string()).read();
  ASSERT_EQ(moved.size(), 2u);
  EXPECT_EQ(moved[1].tile, "t1");
  const std::vector<JournalEntry> current = journal.read();
  ASSERT_EQ(current.size(), 1u);
  EXPECT_EQ(current[0].tile, "t2");
  fs::remove(path);
  fs::remove(aside);
}

TEST(Journal, ALineCutShortByACrashIsIgnored) {
  const fs::path path = scratch("cut");
  const Journal journal(path.string());
  journal.startRun("2 tiles");
  {
    std::ofstream out(path, std::ios::app);
    out << "1\t2026-12-02T00:00:00\tdone\tt9";  // killed in the middle of the line
  }
  EXPECT_EQ(journal.read().size(), 1u);
  journal.append(1, "done", "t1", "ok");  // starts on a line of its own
  const std::vector<JournalEntry> entries = journal.read();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[1].tile, "t1");
  EXPECT_EQ(completedTiles(entries), (std::set<std::string>{"t1"}));
  fs::remove(path);
}

TEST(Journal, ReadFromFollowsTheLinesAppendedSince) {
  const fs::path path = scratch("follow");
  const Journal journal(path.string());
  std::uint64_t offset = 0;
  EXPECT_TRUE(journal.readFrom(offset).empty());  // no file yet
  EXPECT_EQ(offset, 0u);
  journal.startRun("2 tiles");
  journal.append(1, "done", "t1", "3 candidates");
  std::vector<JournalEntry> entries = journal.readFrom(offset);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[1].tile, "t1");
  EXPECT_EQ(offset, fs::file_size(path));
  EXPECT_TRUE(journal.readFrom(offset).empty());  // nothing new
  {
    std::ofstream out(path, std::ios::app);
    out << "1\t2026-12-02T00:00:00\tfailed\tt2\tcut";  // a line not ended yet
  }
  EXPECT_TRUE(journal.readFrom(offset).empty());
  EXPECT_LT(offset, fs::file_size(path));  // the partial line is read again next time
  {
    std::ofstream out(path, std::ios::app);
    out << " short\n";
  }
  entries = journal.readFrom(offset);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].tile, "t2");
  EXPECT_EQ(entries[0].detail, "cut short");
  EXPECT_EQ(offset, fs::file_size(path));
  fs::remove(path);
}

TEST(TileClaim, HeldByOneOpenFileAtATimeAndFreedWithIt) {
  const fs::path path = scratch("claim");
  {
    std::optional<TileClaim> first = TileClaim::tryTake(path.string());
    ASSERT_TRUE(first.has_value());
    EXPECT_TRUE(fs::exists(path));
    // Another open file, in this process as in another, cannot take it meanwhile.
    EXPECT_FALSE(TileClaim::tryTake(path.string()).has_value());
    const int fd = ::open(path.c_str(), O_RDONLY);
    EXPECT_NE(::flock(fd, LOCK_EX | LOCK_NB), 0);
    ::close(fd);
    // Moved, still held.
    TileClaim moved = std::move(*first);
    first.reset();
    EXPECT_FALSE(TileClaim::tryTake(path.string()).has_value());
  }
  // Let go with the object: the next run takes it; the file stays.
  EXPECT_TRUE(TileClaim::tryTake(path.string()).has_value());
  EXPECT_TRUE(fs::exists(path));
  // Held by a process that is gone: free (a child locks it, then exits without unlocking).
  const pid_t child = ::fork();
  if (child == 0) {
    const int fd = ::open(path.c_str(), O_RDWR);
    _exit(fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(TileClaim::tryTake(path.string()).has_value());
  // A claim that cannot be made names its file.
  try {
    (void)TileClaim::tryTake((fs::temp_directory_path() / "octarc-no-such-dir" / "t1").string());
    ADD_FAILURE() << "no IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("octarc-no-such-dir/t1: cannot open"), std::string::npos)
        << e.what();
  }
  fs::remove(path);
}

}  // namespace
}  // namespace octarc
