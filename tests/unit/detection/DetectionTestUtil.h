// source-extractor runs of the detection tests; the FITS basics are in tests/support/
// FitsTestFiles.h, the program checks in tests/support/TestCommands.h.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include "FitsTestFiles.h"
#include "TestCommands.h"
#include "TestPaths.h"

namespace octarc::test {

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

}  // namespace octarc::test
