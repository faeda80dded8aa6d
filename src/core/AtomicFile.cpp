#include "octarc/core/AtomicFile.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "octarc/core/Error.h"

namespace octarc {

namespace {
std::atomic<int> tempCounter{0};
}

AtomicFile::AtomicFile(std::string finalPath) : finalPath_(std::move(finalPath)) {
  std::filesystem::path p(finalPath_);
  std::filesystem::path dir = p.parent_path();
  std::string name = "." + p.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                     std::to_string(tempCounter++);
  tempPath_ = (dir.empty() ? std::filesystem::path(name) : dir / name).string();
  std::remove(tempPath_.c_str());
}

AtomicFile::~AtomicFile() {
  if (!committed_) std::remove(tempPath_.c_str());
}

void AtomicFile::commit() {
  if (std::rename(tempPath_.c_str(), finalPath_.c_str()) != 0) {
    throw IoError(finalPath_ + ": cannot write (" + std::strerror(errno) + ")");
  }
  committed_ = true;
}

}  // namespace octarc
