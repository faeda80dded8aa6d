// The journal of a batch: OUTPUT_DIR/journal.txt, one line per event, only ever appended:
//
//   RUN <tab> UTC time <tab> EVENT <tab> TILE <tab> DETAIL
//
// EVENT is `start` (TILE "-", DETAIL: tiles, ranks, array share), `done` (DETAIL: candidates,
// seconds, rank) or `failed` (DETAIL: the error). A `done` line is written only after the
// tile's folder is complete and in place, so a tile is complete exactly when a `done` line
// names it; a rerun redoes every other tile. RUN counts the batch runs into this directory
// (1, 2, ...), so the journal shows which tiles each run did.
//
// Lines are appended with O_APPEND under an exclusive flock and synced, so that the tasks of a
// job array can share one journal. A line cut short by a crash is ignored when reading.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace octarc {

struct JournalEntry {
  int run = 0;
  std::string timeUtc;
  std::string event;  // start, done, failed
  std::string tile;
  std::string detail;
};

class Journal {
 public:
  // The journal at `path` (made by the first append).
  explicit Journal(std::string path);

  const std::string& path() const { return path_; }
  // Every complete line; none when the file does not exist. IoError when it cannot be read.
  std::vector<JournalEntry> read() const;
  // Appends a `start` line for the next run number and returns that number.
  int startRun(const std::string& detail) const;
  // Appends one line (tabs and line breaks in the fields become blanks); IoError on failure.
  void append(int run, const std::string& event, const std::string& tile,
              const std::string& detail) const;
  // The same, and returns every line (this one included) read under the same lock: of the job
  // array's tasks, the one that appends the last line sees every other line.
  std::vector<JournalEntry> appendAndRead(int run, const std::string& event,
                                          const std::string& tile, const std::string& detail) const;

 private:
  std::string path_;
};

// The tiles that a `done` line names.
std::set<std::string> completedTiles(const std::vector<JournalEntry>& entries);

}  // namespace octarc
