// .conv filter masks: the reader, then the mask applied to a small image as the detection
// filter does.
#include <cstddef>
#include <cstdint>
#include <string>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/detection/Filter.h"
#include "octarc/sexcompat/ConvFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = octarc::fuzz::writeInput(data, size, "mask.conv");
  try {
    std::vector<std::string> warnings;
    const octarc::ConvKernel kernel = octarc::sexcompat::readConvFile(path, &warnings);
    octarc::ImageF image(9, 7);
    for (std::int64_t i = 0; i < image.size(); ++i) image[i] = float(i % 5) - 1.5f;
    octarc::applyFilter(image, kernel);
  } catch (const octarc::Error&) {
  }
  return 0;
}
