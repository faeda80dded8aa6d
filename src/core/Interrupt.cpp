#include "octarc/core/Interrupt.h"

#include <dirent.h>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace octarc {

namespace {

// The registry is a fixed array so that the signal handler can walk it without allocating or
// locking (only async-signal-safe calls: unlink, rmdir, write, _exit).
constexpr int kSlots = 1024;
constexpr std::size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kFilling = 1, kFile = 2, kDirectory = 3, kTree = 4 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes]{};
};

// constinit: all zeros, so the 4 MB lie in .bss and no page is touched at start-up (a dynamic
// initialiser writing each slot's state cost every process about 15 ms, most of it in page faults).
constinit Slot gSlots[kSlots];
std::atomic<int> gDeferDepth{0};
std::atomic<int> gPendingSignal{0};
std::atomic<bool> gOutputsComplete{false};
std::atomic_flag gEnding = ATOMIC_FLAG_INIT;
// Set by a handler before it looks at gDeferDepth, and while the process ends: a thread about to
// rename outputs into place (DeferInterrupts) waits while it is set, so that no rename starts
// while a handler removes the registered temporaries (a temporary directory renamed into place
// during its removal was left behind empty under its final name).
std::atomic<bool> gCleaning{false};
char gPrefix[256] = "octarc";
// PiecesAccount's texts, fixed before the run.
constexpr std::size_t kAccountBytes = 1024;
std::atomic<bool> gCountPieces{false}, gShowCount{false};
char gPiecesBefore[kAccountBytes], gPiecesAfter[kAccountBytes];
char gFinalWritten[kAccountBytes], gFinalNotWritten[kAccountBytes];
std::atomic<long long> gPiecesKept{0};
std::atomic<bool> gNextOutputsFinal{false};
std::atomic<bool> gFinalOutputsWritten{false};
bool gStderrIsTerminal = false;

// The line a signal prints, put together first and written at once: the ranks of an MPI job
// share one stderr, and lines written piece by piece would interleave there. A pipe takes a
// write of up to 4096 bytes whole.
char gLine[4096];
std::size_t gLineBytes = 0;

void writeText(const char* text) {
  const std::size_t n = std::min(std::strlen(text), sizeof gLine - gLineBytes);
  std::memcpy(gLine + gLineBytes, text, n);
  gLineBytes += n;
}

void flushLine() {
  const char* text = gLine;
  std::size_t left = gLineBytes;
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= std::size_t(n);
  }
}

// `n` in decimal, with no allocation.
void writeCount(long long n) {
  char digits[24];
  int at = int(sizeof digits);
  digits[--at] = '\0';
  do {
    digits[--at] = char('0' + n % 10);
    n /= 10;
  } while (n > 0 && at > 0);
  writeText(digits + at);
}

void copyText(char* to, const std::string& text) {
  std::strncpy(to, text.c_str(), kAccountBytes - 1);
  to[kAccountBytes - 1] = '\0';
}

const char* signalName(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

// Removes directory `name` of `parentFd` with everything in it, with system calls only (no
// allocation: one fixed buffer per depth; deeper than kTreeDepth levels is left in place).
constexpr int kTreeDepth = 8;
struct LinuxDirent64 {
  ino64_t inode;
  off64_t offset;
  unsigned short length;
  unsigned char type;
  char name[1];
};
alignas(8) char gTreeBuffers[kTreeDepth][4096];

void removeTreeAt(int parentFd, const char* name, int depth) {
  const int fd = ::openat(parentFd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  if (depth < kTreeDepth) {
    char* buffer = gTreeBuffers[depth];
    // Twice over: a file another thread created during the first pass goes in the second.
    for (int pass = 0; pass < 2; ++pass) {
      ::lseek(fd, 0, SEEK_SET);
      for (;;) {
        const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof gTreeBuffers[depth]);
        if (n <= 0) break;
        for (long at = 0; at < n;) {
          const auto* entry = reinterpret_cast<const LinuxDirent64*>(buffer + at);
          at += entry->length;
          if (std::strcmp(entry->name, ".") == 0 || std::strcmp(entry->name, "..") == 0) continue;
          // A file system that does not report entry types (DT_UNKNOWN) says EISDIR for a
          // directory.
          if (entry->type == DT_DIR ||
              (::unlinkat(fd, entry->name, 0) != 0 && (errno == EISDIR || errno == EPERM))) {
            removeTreeAt(fd, entry->name, depth + 1);
            buffer = gTreeBuffers[depth];
          }
        }
      }
    }
  }
  ::close(fd);
  ::unlinkat(parentFd, name, AT_REMOVEDIR);
}

// Ends the process after a signal, removing every registered temporary file and directory (an
// output already renamed into place is no longer registered). `heldBack`: the signal waited for a
// set of outputs to be renamed into place, which are therefore complete.
[[noreturn]] void endAfterSignal(int sig, bool heldBack) {
  if (gEnding.test_and_set()) {
    // Another thread is already ending the process.
    for (;;) ::pause();
  }
  gCleaning.store(true);
  int removed = 0;
  for (Slot& s : gSlots) {
    if (s.state.load() == kFile) {
      ::unlink(s.path);
      ++removed;
    }
  }
  // Directories last, newest first: a directory holding registered files is empty by now.
  for (int i = kSlots - 1; i >= 0; --i) {
    if (gSlots[i].state.load() == kDirectory) {
      ::rmdir(gSlots[i].path);
      ++removed;
    } else if (gSlots[i].state.load() == kTree) {
      removeTreeAt(AT_FDCWD, gSlots[i].path, 0);
      ++removed;
    }
  }
  if (gStderrIsTerminal) writeText("\n");  // end a progress bar's line
  writeText(gPrefix);
  writeText(": interrupted by ");
  writeText(signalName(sig));
  if (gCountPieces.load()) {
    writeText(gPiecesBefore);
    if (gShowCount.load()) {
      writeCount(gPiecesKept.load());
      writeText(gPiecesAfter);
      writeText(gFinalOutputsWritten.load() ? gFinalWritten : gFinalNotWritten);
    }
    writeText("\n");
  } else if (heldBack) {
    writeText(" while the outputs were renamed into place; they are complete\n");
  } else if (gOutputsComplete.load() && removed == 0) {
    writeText(" after its outputs were written; they are complete\n");
  } else {
    writeText("; no output written\n");
  }
  flushLine();
  ::_exit(128 + sig);
}

extern "C" void onInterrupt(int sig) {
  // gCleaning before gDeferDepth, as DeferInterrupts does the reverse (both sequentially
  // consistent): either this handler sees the renames begun and defers to them, or they wait.
  const bool alreadyCleaning = gCleaning.exchange(true);
  if (gDeferDepth.load() > 0) {
    gPendingSignal.store(sig);
    // The renames may have finished between the test and the store: then end here.
    if (gDeferDepth.load() > 0 || gPendingSignal.exchange(0) == 0) {
      if (!alreadyCleaning) gCleaning.store(false);
      return;
    }
    endAfterSignal(sig, true);
  }
  endAfterSignal(sig, false);
}

}  // namespace

void installInterruptCleanup(const std::string& messagePrefix) {
  std::strncpy(gPrefix, messagePrefix.c_str(), sizeof gPrefix - 1);
  gPrefix[sizeof gPrefix - 1] = '\0';
  gStderrIsTerminal = ::isatty(STDERR_FILENO) == 1;
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  // A second signal during the cleanup must not interrupt it on the same thread: that handler
  // would wait (pause) for the first, which could then never finish.
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&action.sa_mask, sig);
  action.sa_flags = SA_RESTART;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &action, nullptr);
}

int removeTreeOnInterrupt(const std::string& path) {
  const int slot = removeOnInterrupt(path, true);
  gSlots[slot].state.store(kTree);
  return slot;
}

int removeOnInterrupt(const std::string& path, bool isDirectory) {
  if (path.size() >= kPathBytes) {
    throw std::length_error("output path longer than " + std::to_string(kPathBytes - 1) +
                            " bytes: " + path.substr(0, 80) + "...");
  }
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (gSlots[i].state.compare_exchange_strong(expected, kFilling)) {
      std::memcpy(gSlots[i].path, path.c_str(), path.size() + 1);
      gSlots[i].state.store(isDirectory ? kDirectory : kFile);
      return i;
    }
  }
  throw std::length_error("more than " + std::to_string(kSlots) + " outputs open at once");
}

void markOutputsComplete() {
  gOutputsComplete.store(true);
  if (gNextOutputsFinal.load()) gFinalOutputsWritten.store(true);
}

void accountPiecesOnInterrupt(const PiecesAccount& account) {
  gCountPieces.store(false);  // the handler does not read texts being copied
  copyText(gPiecesBefore, account.before);
  copyText(gPiecesAfter, account.after);
  copyText(gFinalWritten, account.finalWritten);
  copyText(gFinalNotWritten, account.finalNotWritten);
  gShowCount.store(account.counted);
  gCountPieces.store(true);
}

void notePieceKept() {
  ++gPiecesKept;
}

void markNextOutputsFinal() {
  gNextOutputsFinal.store(true);
}

void forgetOnInterrupt(int slot) {
  if (slot >= 0 && slot < kSlots) gSlots[slot].state.store(kFree);
}

DeferInterrupts::DeferInterrupts() {
  ++gDeferDepth;
  // A handler that decided before this increment to remove the temporaries ends the process;
  // one that sees it defers to these renames and clears gCleaning.
  while (gCleaning.load()) ::sched_yield();
}

DeferInterrupts::~DeferInterrupts() {
  if (--gDeferDepth == 0) {
    const int sig = gPendingSignal.exchange(0);
    if (sig != 0) endAfterSignal(sig, true);
  }
}

}  // namespace octarc
