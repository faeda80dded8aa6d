// Shell commands and the programs the tests compare with (source-extractor, fitsverify,
// astropy): run, capture the output, skip when a program is missing.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "TestPaths.h"

namespace octarc::test {

// Runs a shell command (its output goes to the test's output); returns its exit status, or -1
// when it did not exit normally.
inline int run(const std::string& command) {
  const int rc = std::system(command.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Runs a shell command with its output and errors discarded; returns its exit status.
inline int runQuiet(const std::string& command) {
  return run(command + " >/dev/null 2>&1");
}

// Runs a shell command; returns its exit status (-1 when it could not run or did not exit
// normally) and, in *output when given, its standard output.
inline int runCommand(const std::string& command, std::string* output = nullptr) {
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return -1;
  std::string text;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, n);
  const int status = ::pclose(pipe);
  if (output != nullptr) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The standard output of a shell command ("" when it could not run).
inline std::string commandOutput(const std::string& command) {
  std::string output;
  runCommand(command, &output);
  return output;
}

// True when `name` is a program on PATH.
inline bool haveProgram(const std::string& name) {
  return runQuiet("command -v '" + name + "'") == 0;
}

inline bool haveSourceExtractor() {
  return runQuiet("source-extractor -v") == 0;
}

inline bool haveFitsverify() {
  return haveProgram("fitsverify");
}

// True when /usr/bin/python3 with astropy is available (the reference for some tests).
inline bool haveAstropy() {
  static const bool ok = runQuiet("/usr/bin/python3 -c 'import astropy.wcs'") == 0;
  return ok;
}

}  // namespace octarc::test

// Skips the test (fails it on the CI machine) when a program it runs is not installed.
#define OCTARC_REQUIRE_PROGRAM(name) \
  if (!::octarc::test::haveProgram(name)) OCTARC_SKIP_MISSING() << (name) << " not installed"

#define OCTARC_REQUIRE_SOURCE_EXTRACTOR()                                                      \
  if (!::octarc::test::haveSourceExtractor()) OCTARC_SKIP_MISSING() << "source-extractor not " \
                                                                       "found"
