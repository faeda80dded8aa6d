// SExtractor catalogs given as INPUT_CATALOG (FITS_LDAC, FITS_1.0): the structure checks, the
// LDAC_IMHEAD cell and the run values octarc takes from it (SEXBKGND, SEXBKDEV, SEXGAIN,
// SEXTHLD, SEXATHLD).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "FuzzInput.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/Error.h"
#include "octarc/run/PreparedImage.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (octarc::fuzz::expandsTooMuch(data, size)) return 0;
  const std::string path = octarc::fuzz::writeInput(data, size, "catalog.ldac");
  try {
    for (const octarc::InputCatalogPart& part : octarc::readInputCatalog(path)) {
      octarc::catalogRunValues(part, path);
    }
  } catch (const octarc::Error&) {
  }
  return 0;
}
