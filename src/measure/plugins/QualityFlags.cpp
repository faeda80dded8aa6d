#include "octarc/measure/plugins/QualityFlags.h"

namespace octarc {

std::vector<ColumnSpec> QualityFlags::columns() const {
  return {{"OCT_FLAGS", "octarc flags (see README: Flags)", "", "meta.code.qual", ColumnType::Int16,
           "%3d"}};
}

void QualityFlags::measure(const Segment&, const MeasureContext&, ObjectState& state,
                           const RowWriter& out) const {
  out.set(0, state.octFlags);
}

}  // namespace octarc
