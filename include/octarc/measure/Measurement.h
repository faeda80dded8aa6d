// The interface of one measurement group: it declares its columns before any pixel is read,
// then fills them for each object. The arithmetic lives in pure functions (MomentsMath.h) that
// tests call directly; a Measurement only adapts it to columns.
#pragma once

#include <string>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/detection/Segment.h"
#include "octarc/measure/MeasureContext.h"
#include "octarc/measure/ObjectState.h"

namespace octarc {

// Where a measurement writes its values: column indices are positions in its own columns()
// list; columns the user did not request are silently dropped.
class RowWriter {
 public:
  RowWriter(double* row, const int* offsets) : row_(row), offsets_(offsets) {}
  void set(int column, double value, int element = 0) const {
    const int o = offsets_[column];
    if (o >= 0) row_[o + element] = value;
  }
  bool wanted(int column) const { return offsets_[column] >= 0; }

 private:
  double* row_;
  const int* offsets_;
};

class Measurement {
 public:
  virtual ~Measurement() = default;
  // Short identifier, e.g. "IsophotalShape".
  virtual std::string name() const = 0;
  // Every column this measurement can fill.
  virtual std::vector<ColumnSpec> columns() const = 0;
  // Names of measurements whose results (in ObjectState) this one reads.
  virtual std::vector<std::string> dependencies() const { return {}; }
  // Computes this measurement for one object: reads pixels/context and earlier results in
  // `state`, stores its own results in `state`, writes requested columns through `out`.
  virtual void measure(const Segment& segment, const MeasureContext& context, ObjectState& state,
                       const RowWriter& out) const = 0;
};

}  // namespace octarc
