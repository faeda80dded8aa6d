#include "octarc/core/AtomicFile.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "octarc/core/Error.h"
#include "octarc/core/Interrupt.h"

namespace octarc {

namespace fs = std::filesystem;

namespace {

std::atomic<int> tempCounter{0};

// True when `text` is "<pid>.<n>" and process pid no longer exists.
bool namesDeadProcess(const std::string& text) {
  const std::size_t dot = text.find('.');
  if (dot == 0 || dot == std::string::npos || dot + 1 == text.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (i != dot && (text[i] < '0' || text[i] > '9')) return false;
  }
  const long pid = std::strtol(text.substr(0, dot).c_str(), nullptr, 10);
  if (pid <= 0 || pid == long(::getpid())) return false;
  return ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}

// Removes the temporaries of `name` in `dir` left by processes that are gone (a run killed by
// SIGKILL): ".<name>.tmp.<pid>.<n>", and "..<name>.tmp.<pid>.<n>.tmp.<pid>.<m>" for a writer
// that was itself given a temporary name (OutputFiles::write).
void removeStaleTemporaries(const fs::path& dir, const std::string& name) {
  const std::string marker = name + ".tmp.";
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    const std::size_t dots = entry.find_first_not_of('.');
    if (dots == 0 || dots == std::string::npos || entry.compare(dots, marker.size(), marker) != 0) {
      continue;
    }
    // The rest is "<pid>.<n>" followed by dots - 1 times ".tmp.<pid>.<n>".
    std::string rest = entry.substr(dots + marker.size());
    bool stale = true;
    for (std::size_t k = 0; k < dots && stale; ++k) {
      const std::size_t next = rest.find(".tmp.");
      stale =
          (next == std::string::npos) == (k + 1 == dots) && namesDeadProcess(rest.substr(0, next));
      rest = next == std::string::npos ? std::string() : rest.substr(next + 5);
    }
    if (stale) {
      std::error_code ignored;
      fs::remove_all(it->path(), ignored);  // a temporary directory goes with its contents
    }
  }
}

}  // namespace

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw IoError(path + ": cannot write");
}

bool createFileExclusive(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return false;
    throw IoError(path + ": cannot create (" + std::strerror(errno) + ")");
  }
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : EIO;  // a write of 0 bytes sets no errno
      ::close(fd);
      ::unlink(path.c_str());  // no partial file for the next process to wait on
      throw IoError(path + ": cannot write (" + std::strerror(e) + ")");
    }
    done += std::size_t(n);
  }
  if (::close(fd) != 0) {
    const int e = errno;
    ::unlink(path.c_str());
    throw IoError(path + ": cannot write (" + std::strerror(e) + ")");
  }
  return true;
}

bool holdsMarker(const std::string& dir, const std::string& marker, const std::string& text) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  std::FILE* f = std::fopen((fs::path(dir) / marker).c_str(), "rb");
  if (f == nullptr) return false;
  std::string content(text.size() + 1, '\0');
  const std::size_t n = std::fread(content.data(), 1, content.size(), f);
  std::fclose(f);
  return n == text.size() && content.compare(0, n, text) == 0;
}

AtomicFile::AtomicFile(std::string finalPath) : finalPath_(std::move(finalPath)) {
  const fs::path p(finalPath_);
  const fs::path dir = p.parent_path();
  // A temporary name's own stale temporaries are those of its target.
  std::string target = p.filename().string();
  if (const std::size_t at = target.find(".tmp."); target[0] == '.' && at != std::string::npos) {
    target = target.substr(1, at - 1);
  }
  removeStaleTemporaries(dir, target);
  const std::string name = "." + p.filename().string() + ".tmp." + std::to_string(::getpid()) +
                           "." + std::to_string(tempCounter++);
  tempPath_ = (dir.empty() ? fs::path(name) : dir / name).string();
  interruptSlot_ = removeOnInterrupt(tempPath_);
  std::remove(tempPath_.c_str());
}

AtomicFile::~AtomicFile() {
  if (!committed_) std::remove(tempPath_.c_str());
  forgetOnInterrupt(interruptSlot_);
}

void AtomicFile::commit() {
  if (std::rename(tempPath_.c_str(), finalPath_.c_str()) != 0) {
    throw IoError(finalPath_ + ": cannot write (" + std::strerror(errno) + ")");
  }
  committed_ = true;
  forgetOnInterrupt(interruptSlot_);
  interruptSlot_ = -1;
}

const AtomicFile& OutputFiles::add(const std::string& finalPath) {
  if (finalPath.empty()) throw ConfigError("an output file name is empty");
  for (const std::unique_ptr<AtomicFile>& f : files_) {
    if (fs::path(f->finalPath()).lexically_normal() == fs::path(finalPath).lexically_normal()) {
      throw ConfigError(finalPath + ": given twice as an output of the same run");
    }
  }
  const fs::path dir = fs::path(finalPath).parent_path();
  const std::string dirText = dir.empty() ? std::string(".") : dir.string();
  std::error_code ec;
  if (!fs::is_directory(dirText, ec)) {
    throw IoError(finalPath + ": cannot write (directory " + dirText + " does not exist)");
  }
  if (::access(dirText.c_str(), W_OK | X_OK) != 0) {
    throw IoError(finalPath + ": cannot write (directory " + dirText + ": " + std::strerror(errno) +
                  ")");
  }
  if (fs::is_directory(finalPath, ec)) {
    throw IoError(finalPath + ": cannot write (it is a directory)");
  }
  files_.push_back(std::make_unique<AtomicFile>(finalPath));
  return *files_.back();
}

void OutputFiles::write(std::size_t i,
                        const std::function<void(const std::string& path)>& write) const {
  const AtomicFile& f = *files_.at(i);
  auto named = [&f](std::string message) {
    for (std::size_t at; (at = message.find(f.tempPath())) != std::string::npos;) {
      message.replace(at, f.tempPath().size(), f.finalPath());
    }
    return message;
  };
  try {
    write(f.tempPath());
  } catch (const IoError& e) {
    throw IoError(named(e.what()));
  } catch (const ConfigError& e) {
    throw ConfigError(named(e.what()));
  }
}

void OutputFiles::commit() {
  if (files_.empty()) return;
  for (const std::unique_ptr<AtomicFile>& f : files_) {
    std::error_code ec;
    if (!fs::exists(f->tempPath(), ec)) {
      throw IoError(f->finalPath() + ": cannot write (its temporary file was not written)");
    }
  }
  DeferInterrupts hold;
  std::error_code ignored;
  fs::remove(files_.front()->finalPath(), ignored);
  for (std::size_t i = 1; i < files_.size(); ++i) files_[i]->commit();
  files_.front()->commit();
  markOutputsComplete();
}

void AtomicDirectory::checkReplaceable(const std::string& finalPath, const std::string& markerFile,
                                       const std::string& markerText) {
  if (finalPath.empty()) throw ConfigError("an output directory name is empty");
  std::string path = finalPath;
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  std::error_code ec;
  if (fs::exists(path, ec) && !holdsMarker(path, markerFile, markerText)) {
    throw ConfigError(path + ": exists and is not an earlier output of this command (no " +
                      markerFile + " in it); give a new directory name or remove it");
  }
}

AtomicDirectory::AtomicDirectory(std::string finalPath, std::string markerFile,
                                 std::string markerText)
    : finalPath_(std::move(finalPath)),
      markerFile_(std::move(markerFile)),
      markerText_(std::move(markerText)) {
  checkReplaceable(finalPath_, markerFile_, markerText_);
  while (finalPath_.size() > 1 && finalPath_.back() == '/') finalPath_.pop_back();
  std::error_code ec;
  const fs::path p = fs::path(finalPath_).lexically_normal();
  const fs::path parent = p.parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec)) {
    throw IoError(finalPath_ + ": cannot write (directory " + parent.string() + " does not exist)");
  }
  removeStaleTemporaries(parent, p.filename().string());
  const std::string name = "." + p.filename().string() + ".tmp." + std::to_string(::getpid()) +
                           "." + std::to_string(tempCounter++);
  tempPath_ = (parent.empty() ? fs::path(name) : parent / name).string();
  interruptSlot_ = removeTreeOnInterrupt(tempPath_);
  fs::create_directory(tempPath_, ec);
  if (ec) {
    forgetOnInterrupt(interruptSlot_);
    throw IoError(finalPath_ + ": cannot write (" + ec.message() + ")");
  }
}

AtomicDirectory::~AtomicDirectory() {
  std::error_code ignored;
  if (!committed_) fs::remove_all(tempPath_, ignored);
  forgetOnInterrupt(interruptSlot_);
}

void AtomicDirectory::commit() {
  std::error_code ec;
  if (!fs::exists(fs::path(tempPath_) / markerFile_, ec)) {
    throw IoError(finalPath_ + ": cannot write (" + markerFile_ + " was not written)");
  }
  DeferInterrupts hold;
  const std::string aside = tempPath_ + ".old";
  const bool replacing = fs::exists(finalPath_, ec);
  // Checked again: the directory may have changed since the run began.
  if (replacing && !holdsMarker(finalPath_, markerFile_, markerText_)) {
    throw IoError(finalPath_ + ": is no longer an earlier output of this command; not replaced");
  }
  if (replacing && std::rename(finalPath_.c_str(), aside.c_str()) != 0) {
    throw IoError(finalPath_ + ": cannot replace (" + std::strerror(errno) + ")");
  }
  if (std::rename(tempPath_.c_str(), finalPath_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    if (replacing) std::rename(aside.c_str(), finalPath_.c_str());
    throw IoError(finalPath_ + ": cannot write (" + why + ")");
  }
  committed_ = true;
  forgetOnInterrupt(interruptSlot_);
  interruptSlot_ = -1;
  if (replacing) fs::remove_all(aside, ec);
  markOutputsComplete();
}

void refuseOutputOverInput(const std::string& outputPath, const std::string& outputKey,
                           const std::string& inputPath, const std::string& inputKey) {
  if (outputPath.empty() || inputPath.empty()) return;
  // cfitsio syntax ("f.fits[1]") names a file plus an HDU: compare the file.
  auto fileOf = [](const std::string& p) {
    const std::size_t bracket = p.find('[');
    return fs::path(bracket == std::string::npos ? p : p.substr(0, bracket));
  };
  const fs::path out = fileOf(outputPath), in = fileOf(inputPath);
  std::error_code ec;
  const bool same = out.lexically_normal() == in.lexically_normal() ||
                    (fs::exists(out, ec) && fs::equivalent(out, in, ec));
  if (same) {
    throw ConfigError(outputKey + " " + outputPath + " is also the " + inputKey +
                      ": octarc never writes over its inputs; choose another output name");
  }
}

}  // namespace octarc
