#include "octarc/core/DataFiles.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <utility>

#include "octarc/core/Error.h"

// The data directory relative to the executable's directory, from the install layout
// (src/core/CMakeLists.txt).
#ifndef OCTARC_DATA_DIR_FROM_BINDIR
#error "OCTARC_DATA_DIR_FROM_BINDIR must be defined by the build"
#endif

namespace octarc {

namespace {

namespace fs = std::filesystem;

// The running executable (Linux: /proc/self/exe names it even when started through a link).
fs::path executablePath() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw IoError("/proc/self/exe: cannot find the octarc executable (" + ec.message() + ")");
  return exe;
}

// $OCTARC_DATA_DIR, or nullptr when it is unset or empty.
const char* dataDirectoryFromEnvironment() {
  const char* env = std::getenv("OCTARC_DATA_DIR");
  return env != nullptr && *env != '\0' ? env : nullptr;
}

// setDataDirectory's directory (set once, by an embedding program's start-up).
std::string& embeddingDataDirectory() {
  static std::string directory;
  return directory;
}

}  // namespace

void setDataDirectory(std::string directory) {
  embeddingDataDirectory() = std::move(directory);
}

std::string dataDirectory() {
  if (const char* env = dataDirectoryFromEnvironment()) return env;
  if (!embeddingDataDirectory().empty()) return embeddingDataDirectory();
  return (executablePath().parent_path() / OCTARC_DATA_DIR_FROM_BINDIR).lexically_normal().string();
}

std::string dataFile(std::string_view name) {
  const bool fromEnvironment = dataDirectoryFromEnvironment() != nullptr;
  const fs::path dir = dataDirectory();
  const fs::path file = dir / name;
  std::error_code ec;
  if (fs::is_regular_file(file, ec)) return file.string();
  throw IoError(file.string() + ": octarc data file not found (searched " +
                (fromEnvironment ? "OCTARC_DATA_DIR " + dir.string()
                 : !embeddingDataDirectory().empty()
                     ? dir.string()
                     : dir.string() + ", beside the octarc executable; set "
                                      "OCTARC_DATA_DIR for another place") +
                ")");
}

std::string userOrDataFile(const std::string& path) {
  std::error_code ec;
  if (path.empty() || fs::exists(path, ec) || fs::path(path).has_parent_path()) return path;
  const fs::path shipped = fs::path(dataDirectory()) / path;
  if (fs::is_regular_file(shipped, ec)) return shipped.string();
  return path;
}

std::string existingUserOrDataFile(const std::string& path, const std::string& what) {
  const std::string resolved = userOrDataFile(path);
  std::error_code ec;
  if (!path.empty() && fs::exists(resolved, ec)) return resolved;
  const bool bareName = !path.empty() && !fs::path(path).has_parent_path();
  throw IoError(path + ": " + what + " not found" +
                (bareName ? " (neither in the working directory nor in " + dataDirectory() + ")"
                          : std::string()));
}

}  // namespace octarc
