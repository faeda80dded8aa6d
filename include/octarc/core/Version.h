// The octarc version (kept equal to project(VERSION) in CMakeLists.txt; a test checks it).
#pragma once

namespace octarc {

inline constexpr const char* kVersion = "0.1.0";

}  // namespace octarc
