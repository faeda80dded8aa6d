// SExtractor SEGMENTATION check-images: the exact integer reader and the label checks (negative
// labels, levels that do not nest). The input is read as two levels: the file twice, so the
// nesting check runs on real data (a level always nests in itself).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/detection/SegmentationReader.h"
#include "octarc/io/FitsImage.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (octarc::fuzz::expandsTooMuch(data, size)) return 0;
  if (octarc::fuzz::holdsTileCompressedImage(data, size)) return 0;
  const std::string path = octarc::fuzz::writeInput(data, size, "seg.fits");
  try {
    const octarc::ImageHdu header = octarc::readImageHeader(path);
    const double pixels =
        header.header.number("NAXIS1").value_or(0) * header.header.number("NAXIS2").value_or(0);
    if (pixels > double(octarc::fuzz::kMaxFuzzPixels)) return 0;
    octarc::FitsHeader cards;
    octarc::ImageI32 labels = octarc::readIntImage(path, &cards);
    const std::int64_t width = labels.width();
    const std::int64_t height = labels.height();
    octarc::readSegmentation({path, path}, width, height);
  } catch (const octarc::Error&) {
  }
  return 0;
}
