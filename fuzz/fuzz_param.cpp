// .param files: the reader, then the column plan every command builds from it (known and
// unknown names, vector sizes, VECTOR_ASSOC), and one catalog row of that plan.
#include <cstddef>
#include <cstdint>
#include <string>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/core/Table.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/RunSettings.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  octarc::RunSettings settings;
  settings.parametersPath = octarc::fuzz::writeInput(data, size, "columns.param");
  try {
    const octarc::ColumnPlan plan = octarc::planColumns(settings, true);
    octarc::Table table(plan.plan.columns());
    table.appendRow();
  } catch (const octarc::Error&) {
  }
  return 0;
}
