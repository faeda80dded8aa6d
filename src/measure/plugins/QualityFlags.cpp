#include "octarc/measure/plugins/QualityFlags.h"

namespace octarc {

std::vector<OutputColumn> QualityFlags::columns() const {
  return {{{"OCT_FLAGS", "octarc flags (see README: Flags)", "", "meta.code.qual",
            ColumnType::Int16, "%3d"},
           [](const MeasuredObject& o) { return double(o.state.octFlags); }}};
}

}  // namespace octarc
