// Progress of long work on a terminal: one line on stderr with a bar, the rate and the time left.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace octarc {

// Called with (done, total) as work advances; the line ends when done reaches total.
using ProgressFn = std::function<void(std::int64_t done, std::int64_t total)>;

// A progress bar on stderr, or an empty function (nothing shown) when stderr is not a terminal
// or `quiet` is set. `unit` names what is counted ("objects", "systems"). Redraws at most every
// 200 ms. Call it from one thread at a time.
ProgressFn terminalProgress(const std::string& label, const std::string& unit, bool quiet);

// VERBOSE_TYPE FULL: a line "> Time: <stage> <seconds> s" per stage, each the time since the
// previous lap (or since the clock was made), given to `log` when `on`; nothing otherwise.
class StageClock {
 public:
  StageClock(bool on, std::function<void(const std::string&)> log);
  void lap(const char* stage);

 private:
  bool on_;
  std::function<void(const std::string&)> log_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace octarc
