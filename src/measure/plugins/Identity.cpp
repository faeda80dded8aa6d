#include "octarc/measure/plugins/Identity.h"

namespace octarc {

std::vector<OutputColumn> Identity::columns() const {
  return {
      {{"NUMBER", "Running object number", "", "meta.record", ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) { return double(o.segment.number); }},
      {{"THRESH_LEVEL", "Threshold level of the object (1 = lowest)", "", "meta.id.part",
        ColumnType::Int16, "%3d"},
       [](const MeasuredObject& o) { return double(o.segment.level); }},
      {{"PARENT_NUMBER", "NUMBER of the parent one level below (0: none)", "", "meta.id.parent",
        ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) { return double(o.segment.parentNumber); }},
      {{"THRESHOLD", "Detection threshold above background", "count",
        "instr.sensitivity;phot.flux.sb", ColumnType::Float32, "%12.7g"},
       [](const MeasuredObject& o) {
         const std::size_t level = static_cast<std::size_t>(o.segment.level - 1);
         return level < o.context.levels.size() ? o.context.levels[level].thresholdAdu : kNaN;
       }},
  };
}

}  // namespace octarc
