#include "octarc/measure/plugins/Identity.h"

namespace octarc {

namespace {
enum Col { kNumber, kThreshLevel, kParentNumber, kThreshold };
}  // namespace

std::vector<ColumnSpec> Identity::columns() const {
  return {
      {"NUMBER", "Running object number", "", "meta.record", ColumnType::Int32, "%10d"},
      {"THRESH_LEVEL", "Threshold level of the object (1 = lowest)", "", "meta.id.part",
       ColumnType::Int16, "%3d"},
      {"PARENT_NUMBER", "NUMBER of the parent one level below (0: none)", "", "meta.id.parent",
       ColumnType::Int32, "%10d"},
      {"THRESHOLD", "Detection threshold above background", "count",
       "instr.sensitivity;phot.flux.sb", ColumnType::Float32, "%12.7g"},
  };
}

void Identity::measure(const Segment& segment, const MeasureContext& context, ObjectState&,
                       const RowWriter& out) const {
  out.set(kNumber, segment.number);
  out.set(kThreshLevel, segment.level);
  out.set(kParentNumber, segment.parentNumber);
  const std::size_t level = static_cast<std::size_t>(segment.level - 1);
  out.set(kThreshold, level < context.levels.size() ? context.levels[level].thresholdAdu : kNaN);
}

}  // namespace octarc
