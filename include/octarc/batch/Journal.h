// The journal of a batch: OUTPUT_DIR/journal.txt, one line per event, only ever appended:
//
//   RUN <tab> UTC time <tab> EVENT <tab> TILE <tab> DETAIL
//
// EVENT is `start` (TILE "-", DETAIL: tiles, ranks, array share), `done` (DETAIL: candidates,
// seconds, rank), `failed` (DETAIL: the error) or `finished` (TILE "-": the run, or the array
// task, is over). A `done` line is written only after the tile's folder is complete and in
// place; a rerun redoes every tile without one (or whose folder has gone). RUN counts the batch
// runs into this directory (1, 2, ...; each task of a job array is a run of its own), so the
// journal shows which tiles each run did.
//
// Lines are appended with O_APPEND under an exclusive flock and synced, so that the tasks of a
// job array, and batches started at once into one OUTPUT_DIR, can share one journal. A line cut
// short by a crash is ignored when reading.
//
// Runs that share a journal share the tiles through claims (TileClaim): a run searches a tile
// only while it holds the tile's claim, and journals it before letting go.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
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
  // The complete lines from byte `offset` on, and `offset` moved past the last of them: a run
  // follows what other runs append without reading the whole journal again. None when the file
  // does not exist; IoError when it cannot be read.
  std::vector<JournalEntry> readFrom(std::uint64_t& offset) const;
  // Appends a `start` line for the next run number and returns that number. With the journal
  // locked, beforeStart(every line) runs first: it may throw (no line is written), or set the
  // journal aside (rename it) and return true, the start line then opening a new journal.
  int startRun(const std::string& detail,
               const std::function<bool(const std::vector<JournalEntry>&)>& beforeStart = {}) const;
  // A check run with the journal locked before each later line (append, appendWhileLocked): it
  // throws when this run may no longer write (OUTPUT_DIR set aside by another run), and the
  // line is not written.
  void guardAppends(std::function<void()> guard) { guard_ = std::move(guard); }
  // Appends one line (tabs and line breaks in the fields become blanks); IoError on failure.
  void append(int run, const std::string& event, const std::string& tile,
              const std::string& detail) const;
  // The same, then whileLocked(every line, this one included) with the journal still locked:
  // of a job array's tasks, the one that appends the last line sees every other line, and what
  // it does then (the survey outputs) no other task does at the same time.
  void appendWhileLocked(
      int run, const std::string& event, const std::string& tile, const std::string& detail,
      const std::function<void(const std::vector<JournalEntry>&)>& whileLocked) const;

 private:
  std::string path_;
  std::function<void()> guard_;
};

// A run's claim on one tile: an exclusive flock on the tile's lock file (OUTPUT_DIR/claims/NAME),
// taken before the tile is searched and let go once it is journaled. While it lives no other
// process (nor another open file of this one) can take the same claim; it ends with the object
// or with the process, so a killed run leaves its tile free for the next. The lock file stays:
// removing it would let two processes lock two different files of one name.
class TileClaim {
 public:
  // The claim, or nothing when another holds it. IoError naming the file when it cannot be made
  // or locked.
  static std::optional<TileClaim> tryTake(const std::string& path);
  TileClaim(TileClaim&& other) noexcept;
  TileClaim& operator=(TileClaim&& other) noexcept;
  TileClaim(const TileClaim&) = delete;
  TileClaim& operator=(const TileClaim&) = delete;
  ~TileClaim();

 private:
  explicit TileClaim(int fd) : fd_(fd) {}
  int fd_ = -1;
};

// The tiles that a `done` line names.
std::set<std::string> completedTiles(const std::vector<JournalEntry>& entries);

}  // namespace octarc
