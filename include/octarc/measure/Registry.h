// The built-in measurements (one explicit list) and the plan that runs the ones a catalog needs.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "octarc/measure/Measurement.h"

namespace octarc {

// Every built-in measurement, in a valid run order.
std::vector<std::unique_ptr<Measurement>> builtinMeasurements();

// Every column the built-in measurements provide, in registration order (`octarc measure -dp`).
std::vector<ColumnSpec> allBuiltinColumns();

// One requested catalog column: a .param line, `NAME` or `NAME(n)`.
struct ColumnRequest {
  std::string name;
  int repeat = 1;
};

// The measurements one catalog needs, in dependency order, and where their columns go.
class MeasurementPlan {
 public:
  // `requested` is in .param order. Names that no measurement provides and that are not in
  // `external` are appended to *unknown (if given; the caller warns "catalog parameter unknown"
  // as SExtractor does) and skipped; duplicates are ignored. `external` columns (e.g.
  // VECTOR_ASSOC(n), filled by the caller) take their place in the requested order, sized by
  // the request, and measure() leaves them alone. Only measurements that provide a requested
  // column, or that such a measurement depends on, run.
  static MeasurementPlan build(const std::vector<ColumnRequest>& requested,
                               const std::vector<ColumnSpec>& external,
                               std::vector<std::string>* unknown);

  // Output columns, in requested order.
  const std::vector<ColumnSpec>& columns() const { return columns_; }
  // Values per row: the sum of the columns' repeats.
  int rowWidth() const { return rowWidth_; }
  // Names of the measurements that run, in run order.
  std::vector<std::string> measurementNames() const;

  // Measures one object into `row` (rowWidth() doubles). Every built-in column is written (NaN
  // or 0 where undefined); external columns are not touched. Thread-safe: const, no shared state.
  void measure(const Segment& segment, const MeasureContext& context, double* row) const;

 private:
  // One requested column of a step: its value and where it goes in the row.
  struct Fill {
    double (*value)(const MeasuredObject& object);
    int offset;
  };
  struct Step {
    std::shared_ptr<const Measurement> measurement;
    std::vector<Fill> fills;  // the requested columns of this measurement (none for a dependency)
  };
  std::vector<ColumnSpec> columns_;
  std::vector<Step> steps_;
  int rowWidth_ = 0;
};

}  // namespace octarc
