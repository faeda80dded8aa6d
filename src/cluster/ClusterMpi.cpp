// The cluster of MPI ranks (Open MPI's C API). Only the calling (main) thread of a rank makes MPI
// calls (MPI_THREAD_FUNNELED): the root's own share of the tasks runs on a second thread that
// never touches MPI.
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <deque>
#include <iostream>
#include <mutex>
#include <thread>
#include <utility>

#include "octarc/cluster/Cluster.h"

namespace octarc {

namespace {

constexpr int kTagReport = 1;  // worker -> root: the last task's index and report
constexpr int kTagTask = 2;    // root -> worker: the next task's index, -1 for none
constexpr int kTagGather = 3;  // rank -> root: its bytes, size first, then in chunks
constexpr std::int64_t kChunkBytes = std::int64_t(1) << 30;  // MPI counts are int

void sendBytes(const std::string& bytes, int to) {
  const std::int64_t size = std::int64_t(bytes.size());
  MPI_Send(&size, 1, MPI_INT64_T, to, kTagGather, MPI_COMM_WORLD);
  for (std::int64_t at = 0; at < size; at += kChunkBytes) {
    const int n = int(std::min(kChunkBytes, size - at));
    MPI_Send(bytes.data() + at, n, MPI_BYTE, to, kTagGather, MPI_COMM_WORLD);
  }
}

std::string receiveBytes(int from) {
  std::int64_t size = 0;
  MPI_Recv(&size, 1, MPI_INT64_T, from, kTagGather, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string bytes(std::size_t(size), '\0');
  for (std::int64_t at = 0; at < size; at += kChunkBytes) {
    const int n = int(std::min(kChunkBytes, size - at));
    MPI_Recv(bytes.data() + at, n, MPI_BYTE, from, kTagGather, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
  return bytes;
}

}  // namespace

Cluster::Cluster() {
  if (!launchedAsMpiRank()) return;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  }
  usesMpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &ranksOnNode_);
  MPI_Comm_free(&node);
}

Cluster::~Cluster() {
  if (!usesMpi_) return;
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised) MPI_Finalize();
}

void Cluster::distribute(std::int64_t count, const std::function<std::string(std::int64_t)>& work,
                         const std::function<void(std::int64_t, const std::string&)>& collect,
                         const std::function<bool(std::int64_t)>& take) const {
  if (size_ == 1) {
    for (std::int64_t i = 0; i < count; ++i) {
      if (!take || take(i)) collect(i, work(i));
    }
    return;
  }
  if (rank_ != 0) {
    std::int64_t last = -1;
    std::string report;
    for (;;) {
      std::string message(sizeof last, '\0');
      std::memcpy(message.data(), &last, sizeof last);
      message += report;
      MPI_Send(message.data(), int(message.size()), MPI_BYTE, 0, kTagReport, MPI_COMM_WORLD);
      std::int64_t task = -1;
      MPI_Recv(&task, 1, MPI_INT64_T, 0, kTagTask, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (task < 0) return;
      report = work(task);
      last = task;
    }
  }

  // The root: its own tasks on a thread, the other ranks served here.
  std::atomic<std::int64_t> next{0};
  // The next task to hand out, past those take() skips; count when none is left.
  const auto nextTask = [&] {
    std::int64_t i = next++;
    while (i < count && take && !take(i)) i = next++;
    return std::min(i, count);
  };
  std::mutex mutex;
  std::deque<std::pair<std::int64_t, std::string>> done;
  bool ownFinished = false;
  std::exception_ptr ownError;  // from take() on the root's own thread
  std::thread own([&] {
    try {
      for (std::int64_t i; (i = nextTask()) < count;) {
        std::string report = work(i);
        const std::lock_guard lock(mutex);
        done.emplace_back(i, std::move(report));
      }
    } catch (...) {
      next = count;
      const std::lock_guard lock(mutex);
      ownError = std::current_exception();
    }
    const std::lock_guard lock(mutex);
    ownFinished = true;
  });
  try {
    int active = size_ - 1;
    for (;;) {
      std::deque<std::pair<std::int64_t, std::string>> arrived;
      bool finished = false;
      std::exception_ptr error;
      {
        const std::lock_guard lock(mutex);
        arrived.swap(done);
        finished = ownFinished;
        error = ownError;
      }
      if (error) std::rethrow_exception(error);
      for (const auto& [i, report] : arrived) collect(i, report);
      if (active == 0 && finished) break;
      int flag = 0;
      MPI_Status status;
      if (active > 0) MPI_Iprobe(MPI_ANY_SOURCE, kTagReport, MPI_COMM_WORLD, &flag, &status);
      if (!flag) {
        // A poll, not a blocking receive: Open MPI's blocking calls spin a core at full load.
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        continue;
      }
      int bytes = 0;
      MPI_Get_count(&status, MPI_BYTE, &bytes);
      std::string message(std::size_t(bytes), '\0');
      MPI_Recv(message.data(), bytes, MPI_BYTE, status.MPI_SOURCE, kTagReport, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      std::int64_t last = -1;
      std::memcpy(&last, message.data(), sizeof last);
      if (last >= 0) collect(last, message.substr(sizeof last));
      std::int64_t task = nextTask();
      if (task >= count) {
        task = -1;
        --active;
      }
      MPI_Send(&task, 1, MPI_INT64_T, status.MPI_SOURCE, kTagTask, MPI_COMM_WORLD);
    }
  } catch (const std::exception& e) {
    // The other ranks wait for this one: end the whole job rather than leave them waiting.
    next = count;
    own.join();
    std::cerr << "octarc: error on the root rank: " << e.what() << "\n";
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  own.join();
}

std::string Cluster::broadcast(const std::string& bytes) const {
  if (size_ == 1) return bytes;
  std::int64_t size = std::int64_t(bytes.size());
  MPI_Bcast(&size, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  std::string out = rank_ == 0 ? bytes : std::string(std::size_t(size), '\0');
  for (std::int64_t at = 0; at < size; at += kChunkBytes) {
    const int n = int(std::min(kChunkBytes, size - at));
    MPI_Bcast(out.data() + at, n, MPI_BYTE, 0, MPI_COMM_WORLD);
  }
  return out;
}

std::vector<std::string> Cluster::gather(const std::string& local) const {
  if (size_ == 1) return {local};
  if (rank_ != 0) {
    sendBytes(local, 0);
    return {};
  }
  std::vector<std::string> all{local};
  for (int r = 1; r < size_; ++r) all.push_back(receiveBytes(r));
  return all;
}

void Cluster::abortIfFailedAlone(const std::string& message) const {
  if (size_ == 1 || failureShared_) return;
  std::cerr << "octarc (rank " << rank_ << "): error: " << message << "\n";
  MPI_Abort(MPI_COMM_WORLD, 1);
}

void Cluster::raiseIfAnyFailed(const std::exception_ptr& error) const {
  if (size_ == 1) {
    if (error) std::rethrow_exception(error);
    return;
  }
  const int mine = error ? 1 : 0;
  std::vector<int> failed(std::size_t(size_), 0);
  MPI_Allgather(&mine, 1, MPI_INT, failed.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const auto first = std::find(failed.begin(), failed.end(), 1);
  if (first == failed.end()) return;
  failureShared_ = true;
  if (int(first - failed.begin()) == rank_) std::rethrow_exception(error);
  throw PeerFailed();
}

}  // namespace octarc
