#include "octarc/run/MeasurementQueue.h"

#include <algorithm>
#include <optional>

#include "octarc/run/CatalogAssembly.h"

namespace octarc {

namespace {
// A job is this many objects or pixels, whichever comes first: small enough to share out
// evenly, large enough that the locking does not show.
constexpr std::size_t kJobObjects = 256;
constexpr std::size_t kJobPixels = std::size_t(1) << 15;
// The caller waits while this many pixels are queued (8 bytes each in the pixel lists).
constexpr std::size_t kMaxPendingPixels = std::size_t(1) << 20;
}  // namespace

MeasurementQueue::MeasurementQueue(const MeasurementPlan& plan, const MeasureContext& context,
                                   int threads)
    : plan_(plan), context_(context) {
  for (int t = 0; t < threads && threads > 1; ++t) workers_.emplace_back([this] { work(); });
}

MeasurementQueue::~MeasurementQueue() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void MeasurementQueue::add(Segment&& segment, double* row) {
  if (workers_.empty()) {
    measureInto(segment, context_, row);
    return;
  }
  open_.pixels += std::size_t(segment.pixelCount());
  open_.segments.push_back(std::move(segment));
  open_.rows.push_back(row);
  if (open_.segments.size() >= kJobObjects || open_.pixels >= kJobPixels) submit();
}

void MeasurementQueue::measureInto(const Segment& segment, const MeasureContext& context,
                                   double* row) const {
  // Rows may come unset (Table::appendRowUnset): the first write to them happens here, on the
  // measuring thread.
  std::fill_n(row, plan_.rowWidth(), 0.0);
  plan_.measure(segment, context, row);
}

void MeasurementQueue::submit() {
  if (open_.segments.empty()) return;
  std::unique_lock lock(mutex_);
  // A single huge object is always let through, so that the caller never waits forever.
  changed_.wait(lock, [&] {
    return error_ || pendingPixels_ == 0 || pendingPixels_ + open_.pixels <= kMaxPendingPixels;
  });
  if (error_) std::rethrow_exception(error_);
  pendingPixels_ += open_.pixels;
  pending_.push_back(std::move(open_));
  open_ = Job();
  lock.unlock();
  changed_.notify_all();
}

void MeasurementQueue::work() {
  // A WCS serialises its transforms: each worker measures with its own copy.
  std::optional<Wcs> wcs;
  const MeasureContext context = withOwnWcs(context_, wcs);
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return stop_ || !pending_.empty(); });
      if (stop_) return;  // destroyed: queued work is dropped
      job = std::move(pending_.front());
      pending_.pop_front();
      ++busy_;
    }
    try {
      for (std::size_t i = 0; i < job.segments.size(); ++i) {
        measureInto(job.segments[i], context, job.rows[i]);
      }
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    {
      std::lock_guard lock(mutex_);
      pendingPixels_ -= job.pixels;
      --busy_;
    }
    changed_.notify_all();
  }
}

void MeasurementQueue::finish() {
  if (workers_.empty()) return;
  submit();
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return error_ || (pending_.empty() && busy_ == 0); });
  if (error_) std::rethrow_exception(error_);
}

}  // namespace octarc
