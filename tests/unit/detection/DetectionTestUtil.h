// source-extractor utilities for the detection tests; the FITS basics are in
// tests/support/FitsTestFiles.h.
#pragma once

#include <fitsio.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>

#include "FitsTestFiles.h"
#include "TestPaths.h"
#include "octarc/core/Image.h"

namespace octarc::test {

inline bool haveSourceExtractor() {
  return std::system("source-extractor -v > /dev/null 2>&1") == 0;
}

// Runs source-extractor on `image` in `dir` with SExtractor's built-in defaults (-dd) overridden
// by `options`; the catalog is not written. Returns the exit status.
inline int runSourceExtractor(const std::filesystem::path& dir, const std::string& image,
                              const std::string& options) {
  const std::string cmd = "cd '" + dir.string() + "' && source-extractor -dd > default.sex && " +
                          "source-extractor " + image +
                          " -c default.sex -CATALOG_TYPE NONE"
                          " -PARAMETERS_NAME /usr/share/source-extractor/default.param"
                          " -VERBOSE_TYPE QUIET " +
                          options + " > se.log 2>&1";
  return std::system(cmd.c_str());
}

#define OCTARC_REQUIRE_SOURCE_EXTRACTOR()                                                      \
  if (!::octarc::test::haveSourceExtractor()) OCTARC_SKIP_MISSING() << "source-extractor not " \
                                                                       "found"

}  // namespace octarc::test
