// A main() for the fuzz targets outside libFuzzer: each file named on the command line, or found
// (recursively, in name order) in a folder named there, is passed once to LLVMFuzzerTestOneInput,
// and the empty input first, as libFuzzer's -runs=0 does; an input that takes over 30 s fails
// the run, as libFuzzer's -timeout=30 (scripts/fuzz.sh). The sanitizer build of the tests
// replays the seed corpus this way with GCC (fuzz/CMakeLists.txt); exploring new inputs needs
// libFuzzer (clang): scripts/fuzz.sh.
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

constexpr unsigned kTimeoutSeconds = 30;
char gCurrentInput[4096] = "(the empty input)";

// Async-signal-safe: names the input and ends the process.
void onTimeout(int) {
  constexpr char kPrefix[] = "fuzz replay: an input took over 30 s: ";
  (void)!::write(STDERR_FILENO, kPrefix, sizeof kPrefix - 1);
  (void)!::write(STDERR_FILENO, gCurrentInput, std::strlen(gCurrentInput));
  (void)!::write(STDERR_FILENO, "\n", 1);
  ::_exit(1);
}

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "fuzz replay: %s\n", message.c_str());
  std::exit(2);
}

std::vector<std::filesystem::path> inputFiles(int argc, char** argv) {
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path arg = argv[i];
    if (std::filesystem::is_directory(arg)) {
      std::vector<std::filesystem::path> inFolder;
      for (const auto& entry : std::filesystem::recursive_directory_iterator(arg)) {
        if (entry.is_regular_file()) inFolder.push_back(entry.path());
      }
      // An empty corpus would prove nothing.
      if (inFolder.empty()) fail(arg.string() + ": no input in this folder");
      std::sort(inFolder.begin(), inFolder.end());
      files.insert(files.end(), inFolder.begin(), inFolder.end());
    } else if (std::filesystem::is_regular_file(arg)) {
      files.push_back(arg);
    } else {
      fail(arg.string() + ": no such file or folder");
    }
  }
  return files;
}

std::vector<char> readWhole(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) fail(path.string() + ": cannot open");
  std::vector<char> bytes(std::filesystem::file_size(path));
  in.read(bytes.data(), std::streamsize(bytes.size()));
  if (std::size_t(in.gcount()) != bytes.size()) fail(path.string() + ": cannot read it whole");
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE_OR_FOLDER...\n", argv[0]);
    return 2;
  }
  const std::vector<std::filesystem::path> files = inputFiles(argc, argv);
  std::signal(SIGALRM, onTimeout);
  ::alarm(kTimeoutSeconds);
  LLVMFuzzerTestOneInput(nullptr, 0);
  for (const auto& path : files) {
    const std::vector<char> bytes = readWhole(path);
    std::strncpy(gCurrentInput, path.c_str(), sizeof gCurrentInput - 1);
    ::alarm(kTimeoutSeconds);
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  ::alarm(0);
  std::printf("%zu inputs replayed (and the empty one)\n", files.size());
  return 0;
}
