// Atomic output: every file octarc writes is written under a temporary name beside its target and
// renamed over it once complete, so a failing or killed run never leaves a truncated file under
// the final name, and an input is never modified in place (its old inode is untouched).
//
// One output: AtomicFile. The outputs of one run (a catalog and its check-images, one catalog per
// input catalog, ...): OutputFiles, which renames them into place together once every one is
// written, so that a run's outputs appear together or not at all.
//
// Temporary names are "<dir>/.<name>.tmp.<pid>.<n>". They are removed when the run fails, and by
// the interrupt handler on SIGINT/SIGTERM/SIGHUP (core/Interrupt.h). After a SIGKILL they stay;
// the next AtomicFile for the same target removes those whose process no longer exists.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace octarc {

class AtomicFile {
 public:
  // Picks the temporary name and registers it for removal on interrupt; removes stale
  // temporaries of the same target left by processes that no longer exist.
  explicit AtomicFile(std::string finalPath);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  const std::string& tempPath() const { return tempPath_; }
  const std::string& finalPath() const { return finalPath_; }
  // Renames the temporary file to the final path; throws IoError naming the final path.
  void commit();

 private:
  std::string finalPath_;
  std::string tempPath_;
  int interruptSlot_ = -1;
  bool committed_ = false;
};

// The outputs of one run. Add them (before the work starts: add() checks that the directory
// exists and is writable), write each at its tempPath(), then commit() once everything is
// written. Writers that are themselves atomic may be given tempPath() as their target.
class OutputFiles {
 public:
  // Registers an output. ConfigError when `finalPath` is empty or already in the set; IoError
  // naming it when its directory does not exist or is not writable.
  const AtomicFile& add(const std::string& finalPath);
  // Writes output i: calls write(tempPath). An error whose message names the temporary path is
  // rethrown naming the final path instead, which is the name the user knows.
  void write(std::size_t i, const std::function<void(const std::string& path)>& write) const;
  // Renames every output into place with SIGINT/SIGTERM/SIGHUP held back. The first output added
  // is the run's main output (its catalog): an older file of that name is removed first and it is
  // renamed last, so that even after a SIGKILL during the renames, a main output present means
  // the rest of its run is there too.
  void commit();
  bool empty() const { return files_.empty(); }
  std::size_t size() const { return files_.size(); }
  const AtomicFile& operator[](std::size_t i) const { return *files_[i]; }

 private:
  std::vector<std::unique_ptr<AtomicFile>> files_;
};

// A directory of outputs written whole (a search's candidates, stamps and vetting page): made
// under a temporary name beside its target (".<name>.tmp.<pid>.<n>"), filled by the caller, then
// renamed into place by commit(). An existing directory of that name is replaced only when it
// holds `markerFile` with exactly `markerText` in it (an earlier output of the same kind, which
// wrote it): a user's other directory is never removed. Removed, with its contents, when the
// run fails or is interrupted.
class AtomicDirectory {
 public:
  // ConfigError when `finalPath` is empty, or exists and is not a directory holding the
  // marker; IoError when the temporary directory cannot be made.
  AtomicDirectory(std::string finalPath, std::string markerFile, std::string markerText);
  // The constructor's test alone, for a check before any work: ConfigError when `finalPath` is
  // empty, or exists and is not a directory holding the marker.
  static void checkReplaceable(const std::string& finalPath, const std::string& markerFile,
                               const std::string& markerText);
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;
  ~AtomicDirectory();

  const std::string& tempPath() const { return tempPath_; }
  const std::string& finalPath() const { return finalPath_; }
  // Renames the temporary directory into place (the marker file must have been written); the
  // older directory, checked again, is renamed aside first and removed after. IoError naming
  // the final path.
  void commit();

 private:
  std::string finalPath_;
  std::string markerFile_;
  std::string markerText_;
  std::string tempPath_;
  int interruptSlot_ = -1;
  bool committed_ = false;
};

// Writes `text` to the file `path` (an output's temporary path, say), replacing it; IoError
// naming the path when it cannot be written whole.
void writeTextFile(const std::string& path, const std::string& text);

// Makes the file `path` holding `text` when no file of that name exists: of processes racing to
// make it, one alone does. False when it exists; IoError naming it when it cannot be made or
// written whole.
bool createFileExclusive(const std::string& path, const std::string& text);

// True when `dir` is a directory holding the file `marker` whose content is exactly `text`: an
// output directory of a known kind (an AtomicDirectory's, a batch's).
bool holdsMarker(const std::string& dir, const std::string& marker, const std::string& text);

// Throws ConfigError when `outputPath` names the same file as `inputPath` (same path, or the same
// file through a link): `outputKey` and `inputKey` name the options in the message, e.g.
// "CATALOG_NAME x.ldac is also INPUT_CATALOG: ...".
void refuseOutputOverInput(const std::string& outputPath, const std::string& outputKey,
                           const std::string& inputPath, const std::string& inputKey);

}  // namespace octarc
