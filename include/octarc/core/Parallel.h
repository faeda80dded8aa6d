// Splitting work over threads, the one way every stage does it: exceptions thrown by a worker
// reach the caller, and the results never depend on the number of threads because every item
// is computed the same way whichever thread runs it.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace octarc {

// NTHREADS-style request: n > 0 as given, otherwise every hardware thread (at least 1).
inline int resolveThreads(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

// Runs fn(begin, end) on at most `threads` contiguous blocks of [0, n), block 0 on the calling
// thread. The first exception of any block is rethrown once all have finished.
template <typename Fn>
void parallelBlocks(std::int64_t n, int threads, Fn&& fn) {
  threads = static_cast<int>(std::clamp<std::int64_t>(threads, 1, std::max<std::int64_t>(n, 1)));
  if (threads == 1) {
    fn(std::int64_t{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  auto run = [&](int t) {
    try {
      fn(n * t / threads, n * (t + 1) / threads);
    } catch (...) {
      errors[static_cast<std::size_t>(t)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(run, t);
  run(0);
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

// Runs fn(i) for every i in [0, n), items interleaved over the threads (items of uneven cost,
// such as the shorter last mesh row of an image, then spread evenly).
template <typename Fn>
void parallelFor(std::int64_t n, int threads, Fn&& fn) {
  threads = static_cast<int>(std::clamp<std::int64_t>(threads, 1, std::max<std::int64_t>(n, 1)));
  parallelBlocks(threads, threads, [&](std::int64_t t0, std::int64_t t1) {
    for (std::int64_t t = t0; t < t1; ++t) {
      for (std::int64_t i = t; i < n; i += threads) fn(i);
    }
  });
}

}  // namespace octarc
