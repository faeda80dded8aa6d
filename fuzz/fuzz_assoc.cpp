// ASSOC lists: the reader under the settings chosen by the first byte of the input (type,
// selection, weight column or not, ASSOC_DATA), then matches at a few positions.
#include <cstddef>
#include <cstdint>
#include <string>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/sexcompat/Assoc.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  using octarc::sexcompat::AssocSettings;
  const std::uint8_t choice = data[0];
  AssocSettings settings;
  settings.listPath = octarc::fuzz::writeInput(data + 1, size - 1, "objects.list");
  settings.params = (choice & 1) ? std::vector<int>{1, 2, 3} : std::vector<int>{2, 3};
  settings.data = (choice & 2) ? std::vector<int>{0} : std::vector<int>{1, 4};
  settings.type = octarc::sexcompat::AssocType((choice >> 2) % 8);
  settings.selection = octarc::sexcompat::AssocSelection((choice >> 5) % 3);
  settings.radiusPix = 2.5;
  try {
    std::vector<std::string> warnings;
    const octarc::sexcompat::AssocList list =
        octarc::sexcompat::AssocList::load(settings, 3, 100, nullptr, &warnings);
    for (double xy : {1.0, 10.5, 50.0, 99.6}) list.keeps(list.match(xy, xy));
  } catch (const octarc::Error&) {
  }
  return 0;
}
