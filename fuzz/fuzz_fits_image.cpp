// FITS images and their headers: every image reader, the WCS (wcslib) and the header values
// octarc takes from an image (GAIN, SATURATE). Every input must end in success or an
// octarc::Error; a crash, a sanitizer report, a leak or a hang is a bug.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/run/PreparedImage.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (octarc::fuzz::expandsTooMuch(data, size)) return 0;
  if (octarc::fuzz::holdsTileCompressedImage(data, size)) return 0;
  const std::string path = octarc::fuzz::writeInput(data, size, "image.fits");
  try {
    for (const std::string& hdu : octarc::listImageHdus(path)) {
      const octarc::ImageHdu image = octarc::readImageHeader(hdu);
      std::vector<std::string> warnings;
      octarc::headerNonNegative(image.header, "GAIN", hdu, "GAIN 0", warnings);
      octarc::headerNonNegative(image.header, "SATURATE", hdu, "SATUR_LEVEL 0", warnings);
      if (const std::optional<octarc::Wcs> wcs = octarc::Wcs::fromHeader(image.header, hdu)) {
        const auto world = wcs->pixelToJ2000(1.0, 1.0);
        wcs->worldToPixel(world[0], world[1]);
      }
      // NAXIS1/NAXIS2 of a header that has been read are positive (of the uncompressed image
      // for a tile-compressed one).
      const double pixels =
          image.header.number("NAXIS1").value_or(0) * image.header.number("NAXIS2").value_or(0);
      if (pixels <= double(octarc::fuzz::kMaxFuzzPixels)) octarc::readImage(hdu);
    }
  } catch (const octarc::Error&) {
  }
  return 0;
}
