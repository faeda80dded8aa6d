#include "octarc/batch/Journal.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  return text;
}

std::string oneField(std::string s) {
  for (char& c : s) {
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  }
  return s.empty() ? "-" : s;
}

std::vector<JournalEntry> parseJournal(const std::string& text) {
  std::vector<JournalEntry> entries;
  std::size_t at = 0;
  for (std::size_t end; (end = text.find('\n', at)) != std::string::npos; at = end + 1) {
    std::vector<std::string> f;
    std::stringstream line(text.substr(at, end - at));
    for (std::string field; std::getline(line, field, '\t');) f.push_back(field);
    if (f.size() != 5) continue;
    JournalEntry e;
    try {
      e.run = std::stoi(f[0]);
    } catch (const std::exception&) {
      continue;
    }
    e.timeUtc = f[1];
    e.event = f[2];
    e.tile = f[3];
    e.detail = f[4];
    entries.push_back(std::move(e));
  }
  return entries;  // text after the last line break: a line cut short, ignored
}

// An exclusive flock on the open file `fd`, waited for or not: 1 when taken, 0 when `wait` is
// false and another open file holds it, -1 on any other failure (errno says which).
int lockExclusive(int fd, bool wait) {
  while (::flock(fd, LOCK_EX | (wait ? 0 : LOCK_NB)) != 0) {
    if (errno == EINTR) continue;
    return !wait && errno == EWOULDBLOCK ? 0 : -1;
  }
  return 1;
}

// An open journal, locked for as long as it lives.
class LockedJournal {
 public:
  explicit LockedJournal(const std::string& path) : path_(path) {
    // RESTART Y may move the journal aside while this run waits for its lock: the lock then
    // holds the moved file, so it is taken again on the file the path names now.
    for (;;) {
      fd_ = ::open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
      if (fd_ < 0) {
        throw IoError(path + ": cannot open the journal (" + std::strerror(errno) + ")");
      }
      if (lockExclusive(fd_, true) != 1) {
        const int e = errno;
        ::close(fd_);
        throw IoError(path + ": cannot lock the journal (" + std::strerror(e) + ")");
      }
      struct stat locked {};
      struct stat named {};
      if (::fstat(fd_, &locked) != 0 || (::stat(path.c_str(), &named) != 0 && errno != ENOENT)) {
        const int e = errno;
        ::close(fd_);
        throw IoError(path + ": cannot check the journal (" + std::strerror(e) + ")");
      }
      if (locked.st_dev == named.st_dev && locked.st_ino == named.st_ino) return;
      ::close(fd_);  // moved or removed meanwhile (named then all zero): take the new one
    }
  }
  ~LockedJournal() { ::close(fd_); }  // closing releases the lock
  LockedJournal(const LockedJournal&) = delete;
  LockedJournal& operator=(const LockedJournal&) = delete;

  void append(std::string line) {
    // After a crash mid-line the file may end inside a line: start on a line of our own.
    const off_t size = ::lseek(fd_, 0, SEEK_END);
    char last = '\n';
    if (size > 0 && ::pread(fd_, &last, 1, size - 1) == 1 && last != '\n') line.insert(0, "\n");
    std::size_t done = 0;
    while (done < line.size()) {
      const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        throw IoError(path_ + ": cannot write the journal (" + std::strerror(errno) + ")");
      done += std::size_t(n);
    }
    if (::fsync(fd_) != 0 && errno != EINVAL) {
      throw IoError(path_ + ": cannot sync the journal (" + std::strerror(errno) + ")");
    }
  }
  std::string readAll() {
    std::string text;
    char buffer[65536];
    for (off_t at = 0;;) {
      const ssize_t n = ::pread(fd_, buffer, sizeof buffer, at);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw IoError(path_ + ": cannot read the journal (" + std::strerror(errno) + ")");
      if (n == 0) break;
      text.append(buffer, std::size_t(n));
      at += n;
    }
    return text;
  }

 private:
  std::string path_;
  int fd_ = -1;
};

std::string lineOf(int run, const std::string& event, const std::string& tile,
                   const std::string& detail) {
  return std::to_string(run) + "\t" + utcNow() + "\t" + oneField(event) + "\t" + oneField(tile) +
         "\t" + oneField(detail) + "\n";
}

}  // namespace

Journal::Journal(std::string path) : path_(std::move(path)) {}

std::vector<JournalEntry> Journal::read() const {
  std::uint64_t offset = 0;
  return readFrom(offset);
}

std::vector<JournalEntry> Journal::readFrom(std::uint64_t& offset) const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    if (::access(path_.c_str(), F_OK) != 0) return {};
    throw IoError(path_ + ": cannot read the journal");
  }
  in.seekg(std::streamoff(offset));
  std::stringstream text;
  if (in) text << in.rdbuf();  // nothing past the end
  if (in.bad()) throw IoError(path_ + ": cannot read the journal");
  const std::string lines = text.str();
  const std::size_t end = lines.rfind('\n');
  if (end == std::string::npos) return {};  // no complete line yet
  offset += end + 1;
  return parseJournal(lines.substr(0, end + 1));
}

int Journal::startRun(
    const std::string& detail,
    const std::function<bool(const std::vector<JournalEntry>&)>& beforeStart) const {
  const auto start = [&](LockedJournal& journal, const std::vector<JournalEntry>& entries) {
    int last = 0;
    for (const JournalEntry& e : entries) last = std::max(last, e.run);
    journal.append(lineOf(last + 1, "start", "-", detail));
    return last + 1;
  };
  LockedJournal journal(path_);
  const std::vector<JournalEntry> entries = parseJournal(journal.readAll());
  if (beforeStart && beforeStart(entries)) {
    // Set aside: the old one stays locked until the new one starts.
    LockedJournal fresh(path_);
    return start(fresh, parseJournal(fresh.readAll()));
  }
  return start(journal, entries);
}

void Journal::append(int run, const std::string& event, const std::string& tile,
                     const std::string& detail) const {
  LockedJournal journal(path_);
  if (guard_) guard_();
  journal.append(lineOf(run, event, tile, detail));
}

void Journal::appendWhileLocked(
    int run, const std::string& event, const std::string& tile, const std::string& detail,
    const std::function<void(const std::vector<JournalEntry>&)>& whileLocked) const {
  LockedJournal journal(path_);
  if (guard_) guard_();
  journal.append(lineOf(run, event, tile, detail));
  whileLocked(parseJournal(journal.readAll()));
}

std::optional<TileClaim> TileClaim::tryTake(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(path + ": cannot open the tile's claim (" + std::strerror(errno) + ")");
  const int taken = lockExclusive(fd, false);
  if (taken == 1) return TileClaim(fd);
  const int e = errno;
  ::close(fd);
  if (taken == 0) return std::nullopt;
  throw IoError(path + ": cannot lock the tile's claim (" + std::strerror(e) + ")");
}

TileClaim::TileClaim(TileClaim&& other) noexcept : fd_(other.fd_) {
  other.fd_ = -1;
}

TileClaim& TileClaim::operator=(TileClaim&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

TileClaim::~TileClaim() {
  if (fd_ >= 0) ::close(fd_);  // closing lets go of the lock
}

std::set<std::string> completedTiles(const std::vector<JournalEntry>& entries) {
  std::set<std::string> done;
  for (const JournalEntry& e : entries) {
    if (e.event == "done") done.insert(e.tile);
  }
  return done;
}

}  // namespace octarc
