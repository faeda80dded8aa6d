// Splitting work over threads, the one way every stage does it: exceptions thrown by a worker
// reach the caller, and the results never depend on the number of threads because every item
// is computed the same way whichever thread runs it. Three policies:
//   parallelBlocks / parallelFor  static: contiguous blocks, or items interleaved over threads;
//   parallelForDynamic            dynamic: each item to the next free thread (uneven costs);
//   orderedParallel               dynamic, with the results handed over in item order.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
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

// Runs fn(i) for every i in [0, n), each item taken by the next free thread (for items of very
// uneven cost, such as simulated systems). The calling thread works too and, when given, calls
// progress(done) as items finish (at most every 200 ms, and once at the end). The first
// exception (of an item or of progress) stops the handing out of items and is rethrown once
// every thread has stopped.
template <typename Fn>
void parallelForDynamic(std::int64_t n, int threads, Fn&& fn,
                        const std::function<void(std::int64_t done)>& progress = {}) {
  threads = static_cast<int>(std::clamp<std::int64_t>(threads, 1, std::max<std::int64_t>(n, 1)));
  std::atomic<std::int64_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr error;
  std::mutex errorMutex;
  auto last = std::chrono::steady_clock::now();
  auto work = [&](bool reports) {
    for (std::int64_t i = next++; i < n && !stop; i = next++) {
      try {
        fn(i);
        ++done;
        // Inside the try: a progress function may throw too (an interrupt from Python).
        if (reports && progress) {
          const auto now = std::chrono::steady_clock::now();
          if (now - last >= std::chrono::milliseconds(200)) {
            last = now;
            progress(done);
          }
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(errorMutex);
        if (!error) error = std::current_exception();
        stop = true;
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, false);
  work(true);
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(done);
}

// Runs compute(i, state, result) for items 0..count-1 on `threads` workers (each with its own
// default-constructed State, reused from item to item, e.g. scratch buffers) and hands the
// results to emit(result) on the calling thread in item order. At most 4 x threads items are in
// flight, which bounds the memory of finished results waiting for their turn. With one thread,
// everything runs on the calling thread.
template <typename Result, typename State, typename Compute, typename Emit>
void orderedParallel(std::size_t count, int threads, Compute compute, Emit emit) {
  if (threads <= 1 || count <= 1) {
    State state;
    Result result;
    for (std::size_t i = 0; i < count; ++i) {
      compute(i, state, result);
      emit(result);
    }
    return;
  }
  const std::size_t window = 4 * static_cast<std::size_t>(threads);
  std::vector<Result> slots(window);
  std::vector<char> ready(window, 0);
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t nextTask = 0;
  std::size_t emitted = 0;
  bool stop = false;
  std::exception_ptr error;

  auto worker = [&] {
    State state;
    Result result;
    for (;;) {
      std::size_t task = 0;
      {
        std::unique_lock lock(mutex);
        changed.wait(lock,
                     [&] { return stop || nextTask >= count || nextTask < emitted + window; });
        if (stop || nextTask >= count) return;
        task = nextTask++;
      }
      try {
        compute(task, state, result);
      } catch (...) {
        std::lock_guard lock(mutex);
        if (!error) error = std::current_exception();
        stop = true;
        changed.notify_all();
        return;
      }
      {
        std::lock_guard lock(mutex);
        std::swap(slots[task % window], result);
        ready[task % window] = 1;
      }
      changed.notify_all();
    }
  };

  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  try {
    Result result;
    for (std::size_t i = 0; i < count; ++i) {
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return stop || ready[i % window]; });
        if (stop) break;
        std::swap(result, slots[i % window]);
        ready[i % window] = 0;
        ++emitted;
      }
      changed.notify_all();
      emit(result);
    }
  } catch (...) {
    std::lock_guard lock(mutex);
    if (!error) error = std::current_exception();
  }
  {
    std::lock_guard lock(mutex);
    stop = true;
  }
  changed.notify_all();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace octarc
