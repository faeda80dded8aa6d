// The interface of one measurement group: it declares each of its columns together with the code
// that fills it, before any pixel is read, then computes its results for each object. The
// arithmetic lives in pure functions (MomentsMath.h) that tests call directly; a Measurement
// only adapts it to columns.
#pragma once

#include <string>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/core/Segment.h"
#include "octarc/measure/MeasureContext.h"
#include "octarc/measure/ObjectState.h"

namespace octarc {

// What a column sees of one object once its measurement has run.
struct MeasuredObject {
  const Segment& segment;
  const MeasureContext& context;
  const ObjectState& state;
};

// One catalog column and the function that gives its value for an object. Declaring the two
// side by side means no column list can get out of step with the code that fills it. Built-in
// columns are scalars (ColumnSpec::repeat 1).
struct OutputColumn {
  ColumnSpec spec;
  double (*value)(const MeasuredObject& object);
};

class Measurement {
 public:
  virtual ~Measurement() = default;
  // Short identifier, e.g. "IsophotalShape".
  virtual std::string name() const = 0;
  // Every column this measurement can fill, each with its value.
  virtual std::vector<OutputColumn> columns() const = 0;
  // Names of measurements whose results (in ObjectState) this one reads.
  virtual std::vector<std::string> dependencies() const { return {}; }
  // Computes this measurement for one object: reads pixels/context and earlier results in
  // `state` and stores its own results there; the plan then reads the requested columns. A
  // measurement whose columns only read the segment, the context or earlier results computes
  // nothing.
  virtual void measure(const Segment& /*segment*/, const MeasureContext& /*context*/,
                       ObjectState& /*state*/) const {}
};

}  // namespace octarc
