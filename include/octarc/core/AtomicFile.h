// Atomic output: write to a temporary file beside the target, then rename over it. A failing or
// killed run never leaves a truncated file under the final name.
#pragma once

#include <string>

namespace octarc {

class AtomicFile {
 public:
  // Picks a temporary name in the target's directory ("<dir>/.<name>.tmp.<pid>.<n>").
  explicit AtomicFile(std::string finalPath);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  const std::string& tempPath() const { return tempPath_; }
  const std::string& finalPath() const { return finalPath_; }
  // Renames the temporary file to the final path; throws IoError on failure.
  void commit();

 private:
  std::string finalPath_;
  std::string tempPath_;
  bool committed_ = false;
};

}  // namespace octarc
