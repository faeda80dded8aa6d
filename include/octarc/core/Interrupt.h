// Ctrl-C leaves nothing behind: SIGINT, SIGTERM and SIGHUP remove every temporary output file of
// the run (and the provisional outputs and directories it registered), print one line and end the
// process with status 128 + signal number, as shells expect of an interrupted program.
//
// The handler is installed once, by main(). Every AtomicFile registers its temporary path here
// for as long as it exists, so no command needs code of its own. While a set of outputs is being
// renamed into place (DeferInterrupts), a signal waits until the renames are done: the run's
// outputs are then complete, and they are kept.
//
// SIGKILL cannot be caught: a killed run may leave temporary files (hidden names ending in
// ".tmp.<pid>.<n>"), never a truncated file under a final name. The next run writing the same
// output removes the temporaries of processes that no longer exist (see AtomicFile).
#pragma once

#include <string>

namespace octarc {

// Installs the handlers. `messagePrefix` starts the line printed on stderr, e.g. "octarc detect".
void installInterruptCleanup(const std::string& messagePrefix);

// A path removed (unlink, or rmdir for an empty directory) if the run is interrupted, for outputs
// of a multi-step command that exist under their final names before the run is over. Returns a
// slot to pass to forgetOnInterrupt() once the path may stay. Paths longer than 4095 bytes, or
// beyond the registry's 1024 slots, throw std::length_error.
int removeOnInterrupt(const std::string& path, bool isDirectory = false);
void forgetOnInterrupt(int slot);
// A temporary directory removed with everything in it (a directory of outputs written whole,
// AtomicDirectory), with system calls only, as a signal handler may.
int removeTreeOnInterrupt(const std::string& path);

// Called once a run's outputs are all in place (OutputFiles::commit does it): a signal arriving
// afterwards, with nothing left to remove, still ends the process with 128 + signal but says that
// the outputs are complete.
void markOutputsComplete();

// A run that keeps its outputs piece by piece (octarc batch keeps each tile once journaled, then
// writes the survey's files) has a signal print its own account of what is on disk instead:
//   PREFIX: interrupted by SIGINT<before>N<after><final>
// N counts the notePieceKept() calls so far; <final> is `finalWritten` once the outputs committed
// after markNextOutputsFinal() are in place (a signal held back by their renames included), else
// `finalNotWritten`; without `counted`, <before> alone. The texts are copied here, before any
// signal, as the handler may only write; a text longer than 1023 bytes is cut.
struct PiecesAccount {
  std::string before, after, finalWritten, finalNotWritten;
  bool counted = true;
};
void accountPiecesOnInterrupt(const PiecesAccount& account);
void notePieceKept();
void markNextOutputsFinal();

// While one exists (on any thread), SIGINT/SIGTERM/SIGHUP are held back; when the last one is
// destroyed, a signal that arrived meanwhile ends the process (outputs kept, since they are
// complete). Not nestable across threads in a meaningful way: use it around a short sequence of
// renames on one thread.
class DeferInterrupts {
 public:
  DeferInterrupts();
  ~DeferInterrupts();
  DeferInterrupts(const DeferInterrupts&) = delete;
  DeferInterrupts& operator=(const DeferInterrupts&) = delete;
};

}  // namespace octarc
