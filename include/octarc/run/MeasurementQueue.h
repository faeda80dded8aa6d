// Measures objects on worker threads while the caller goes on detecting.
//
// The caller hands over each object together with the table row it goes to. Rows are assigned
// in the caller's order, so the catalog does not depend on the number of threads or on timing;
// the queue only decides when and where each row is filled.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "octarc/core/Segment.h"
#include "octarc/measure/MeasureContext.h"
#include "octarc/measure/Registry.h"

namespace octarc {

class MeasurementQueue {
 public:
  // `plan` and `context` must outlive the queue. threads <= 1 measures in add() itself.
  MeasurementQueue(const MeasurementPlan& plan, const MeasureContext& context, int threads);
  ~MeasurementQueue();
  MeasurementQueue(const MeasurementQueue&) = delete;
  MeasurementQueue& operator=(const MeasurementQueue&) = delete;

  // Queues `segment` to be measured into `row` (plan.rowWidth() values, set here whatever they
  // held, that stay valid until finish() returns). Blocks while too much work is pending, so that
  // pixel lists never pile up. Rethrows the first error of a worker.
  void add(Segment&& segment, double* row);
  // Waits until every queued object is measured; rethrows the first error of a worker.
  void finish();

 private:
  struct Job {
    std::vector<Segment> segments;
    std::vector<double*> rows;
    std::size_t pixels = 0;
  };
  void measureInto(const Segment& segment, const MeasureContext& context, double* row) const;
  void submit();
  void work();

  const MeasurementPlan& plan_;
  const MeasureContext& context_;
  Job open_;  // filled by add(), handed to the workers when large enough
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> pending_;
  std::size_t pendingPixels_ = 0;
  int busy_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> workers_;
};

}  // namespace octarc
