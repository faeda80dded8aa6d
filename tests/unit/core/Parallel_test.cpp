// The work-sharing policies: every item once, whatever the thread count, and exceptions (of an
// item or of the progress function) reaching the caller after every thread has stopped.
#include "octarc/core/Parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

namespace octarc {
namespace {

TEST(Parallel, DynamicVisitsEveryItemOnce) {
  for (int threads : {1, 2, 3, 7}) {
    std::vector<std::atomic<int>> visits(101);
    std::int64_t reported = -1;
    parallelForDynamic(
        101, threads, [&](std::int64_t i) { ++visits[std::size_t(i)]; },
        [&](std::int64_t done) { reported = done; });
    for (const auto& v : visits) EXPECT_EQ(v.load(), 1);
    EXPECT_EQ(reported, 101);  // the last report is the total
  }
}

TEST(Parallel, DynamicRethrowsAnItemsException) {
  std::atomic<int> after{0};
  EXPECT_THROW(parallelForDynamic(1000, 3,
                                  [&](std::int64_t i) {
                                    if (i == 5) throw std::runtime_error("item 5");
                                    if (i > 500) ++after;
                                    std::this_thread::sleep_for(std::chrono::microseconds(20));
                                  }),
               std::runtime_error);
  EXPECT_LT(after.load(), 495);  // the handing out of items stopped
}

// A progress function that throws (as an interrupt from Python does) stops the work and its
// exception reaches the caller; before, it escaped with the other threads still running.
TEST(Parallel, DynamicRethrowsAProgressException) {
  std::atomic<std::int64_t> started{0};
  struct Interrupted {};
  EXPECT_THROW(parallelForDynamic(
                   100000, 2,
                   [&](std::int64_t) {
                     ++started;
                     std::this_thread::sleep_for(std::chrono::microseconds(50));
                   },
                   [](std::int64_t) { throw Interrupted{}; }),
               Interrupted);
  EXPECT_LT(started.load(), 100000);
}

TEST(Parallel, OrderedHandsResultsOverInOrder) {
  struct Square {
    std::size_t value = 0;
  };
  for (int threads : {1, 2, 4}) {
    std::vector<std::size_t> seen;
    orderedParallel<Square, int>(
        50, threads, [](std::size_t i, int&, Square& r) { r.value = i * i; },
        [&](const Square& r) { seen.push_back(r.value); });
    ASSERT_EQ(seen.size(), 50u);
    for (std::size_t i = 0; i < 50; ++i) EXPECT_EQ(seen[i], i * i);
  }
}

}  // namespace
}  // namespace octarc
