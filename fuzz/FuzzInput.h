// Support of the fuzz targets: the readers take file names, so each input is written to a file
// in a temporary directory of this process (in memory under /dev/shm when there is one), under
// the same name every time.
#pragma once

#include <unistd.h>
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace octarc::fuzz {

inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm")
                                           ? "/dev/shm"
                                           : std::filesystem::temp_directory_path();
    std::filesystem::path d = base / ("octarc-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    // Removed when the fuzzer exits normally; a crashed run leaves it for inspection.
    std::atexit([] { std::filesystem::remove_all(scratchDir()); });
    return d;
  }();
  return dir;
}

// Writes the input to scratchDir()/name and returns the path.
inline std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::filesystem::path path = scratchDir() / name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();  // the fuzzer cannot work without its scratch file
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path.string();
}

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Largest image, in pixels, a target reads. Uncompressed images are bounded by the input size;
// a tile-compressed header may legitimately ask for more memory than the fuzzer allows, which
// octarc would try to allocate (and report if it cannot), so such images are only checked,
// not read.
inline constexpr std::int64_t kMaxFuzzPixels = std::int64_t(1) << 22;

// cfitsio grows its buffer for a gzip file in steps of 28800 bytes when the file understates
// its uncompressed size. glibc moves such large blocks without copying them; ASan copies, so an
// input that expands to tens of megabytes would take minutes here, though not in octarc. Gzip
// inputs that expand beyond kMaxExpandedBytes are therefore skipped.
inline constexpr std::size_t kMaxExpandedBytes = std::size_t(4) << 20;

inline bool expandsTooMuch(const std::uint8_t* data, std::size_t size) {
  if (size < 2 || data[0] != 0x1F || data[1] != 0x8B) return false;
  z_stream stream{};
  if (inflateInit2(&stream, 15 + 16) != Z_OK) return false;
  static unsigned char scratch[1 << 16];
  stream.next_in = const_cast<std::uint8_t*>(data);
  stream.avail_in = static_cast<uInt>(size);
  int result = Z_OK;
  while (result == Z_OK && stream.total_out <= kMaxExpandedBytes) {
    stream.next_out = scratch;
    stream.avail_out = sizeof scratch;
    result = inflate(&stream, Z_NO_FLUSH);
  }
  const bool tooMuch = stream.total_out > kMaxExpandedBytes;
  inflateEnd(&stream);
  return tooMuch;
}

// True for an input holding a tile-compressed image (ZIMAGE = T), itself or inside gzip.
// cfitsio 4.2.0's tile decompressors read out of bounds on corrupt tiles (fits_rdecomp, the Rice
// decoder: a SEGV inside cfitsio, reachable from any program that reads such a file): a defect
// of the library, which octarc cannot guard against without decoding the tiles itself. The
// targets leave these inputs out so that they fuzz octarc's code; the README says so.
inline bool holdsTileCompressedImage(const std::uint8_t* data, std::size_t size) {
  const std::string_view key = "ZIMAGE  =";
  if (asText(data, size).find(key) != std::string_view::npos) return true;
  if (size < 2 || data[0] != 0x1F || data[1] != 0x8B) return false;
  z_stream stream{};
  if (inflateInit2(&stream, 15 + 16) != Z_OK) return false;
  std::string out(kMaxExpandedBytes, '\0');
  stream.next_in = const_cast<std::uint8_t*>(data);
  stream.avail_in = static_cast<uInt>(size);
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  inflate(&stream, Z_FINISH);
  out.resize(stream.total_out);
  inflateEnd(&stream);
  return out.find(key) != std::string::npos;
}

}  // namespace octarc::fuzz
