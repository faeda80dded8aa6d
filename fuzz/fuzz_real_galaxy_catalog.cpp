// GalSim RealGalaxyCatalogs (source databases of `octarc simulate lenses --database`): the
// table reader, then every galaxy stamp and PSF a row points to. The input is written as
// "catalog.fits", so rows whose GAL_FILENAME or PSF_FILENAME is catalog.fits read their stamps
// from the input itself.
#include <cstddef>
#include <cstdint>
#include <string>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsImage.h"
#include "octarc/simulation/RealGalaxyCatalog.h"

namespace {

// A stamp is read only when its header says it is small enough (see kMaxFuzzPixels).
bool smallImage(const std::string& path, int hdu) {
  const octarc::ImageHdu header = octarc::readImageHeader(path + "[" + std::to_string(hdu) + "]");
  const double pixels =
      header.header.number("NAXIS1").value_or(0) * header.header.number("NAXIS2").value_or(0);
  return pixels <= double(octarc::fuzz::kMaxFuzzPixels);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (octarc::fuzz::expandsTooMuch(data, size)) return 0;
  if (octarc::fuzz::holdsTileCompressedImage(data, size)) return 0;
  const std::string path = octarc::fuzz::writeInput(data, size, "catalog.fits");
  try {
    const auto catalog = octarc::simulation::RealGalaxyCatalog::load(path, false);
    for (std::size_t i = 0; i < catalog.size() && i < 8; ++i) {
      const auto& entry = catalog.entry(i);
      try {
        if (entry.galaxyPath == path && smallImage(path, entry.galaxyHdu)) catalog.loadGalaxy(i);
      } catch (const octarc::Error&) {
      }
      try {
        if (entry.psfPath == path && smallImage(path, entry.psfHdu)) catalog.loadPsf(i);
      } catch (const octarc::Error&) {
      }
    }
  } catch (const octarc::Error&) {
  }
  return 0;
}
