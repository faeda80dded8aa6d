#include "octarc/core/Progress.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <utility>

namespace octarc {

ProgressFn terminalProgress(const std::string& label, const std::string& unit, bool quiet) {
  if (quiet || !isatty(STDERR_FILENO)) return {};
  const auto start = std::chrono::steady_clock::now();
  auto last = std::make_shared<std::chrono::steady_clock::time_point>(start);
  return [=](std::int64_t done, std::int64_t total) {
    const auto now = std::chrono::steady_clock::now();
    if (done < total && now - *last < std::chrono::milliseconds(200)) return;
    *last = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double fraction = total > 0 ? double(done) / double(total) : 1.0;
    const int width = 30;
    const int filled = int(fraction * width);
    const double rate = elapsed > 0 ? double(done) / elapsed : 0.0;
    const double left = rate > 0 ? double(total - done) / rate : 0.0;
    std::fprintf(stderr, "\r%s [%s%s] %3d%% %.0f %s/s, %.0f s left ", label.c_str(),
                 std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(width - filled), ' ').c_str(), int(100 * fraction), rate,
                 unit.c_str(), left);
    if (done >= total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

StageClock::StageClock(bool on, std::function<void(const std::string&)> log)
    : on_(on && log), log_(std::move(log)), last_(std::chrono::steady_clock::now()) {}

void StageClock::lap(const char* stage) {
  const auto now = std::chrono::steady_clock::now();
  if (on_) {
    char seconds[32];  // to the hundredth: "0.00 s", not "1.1e-05 s"
    std::snprintf(seconds, sizeof seconds, "%.2f",
                  std::chrono::duration<double>(now - last_).count());
    log_(std::string("> Time: ") + stage + " " + seconds + " s");
  }
  last_ = now;
}

}  // namespace octarc
