// Writes a small text file for a test and returns its path.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace octarc::test {

inline std::string writeTextFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path.string();
}

}  // namespace octarc::test
