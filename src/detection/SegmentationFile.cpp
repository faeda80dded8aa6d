// readSegmentation lives apart from segmentsFromLabels so that code using only the in-memory
// form does not pull in the FITS reader.
#include <string>

#include "octarc/core/Error.h"
#include "octarc/detection/SegmentationReader.h"
#include "octarc/io/FitsImage.h"

namespace octarc {

std::vector<Segment> readSegmentation(const std::vector<std::string>& paths, std::int64_t width,
                                      std::int64_t height) {
  std::vector<ImageI32> levels;
  levels.reserve(paths.size());
  for (const std::string& path : paths) {
    // readIntImage rejects floating-point and scaled images, naming the file.
    ImageI32 labels = readIntImage(path);
    if (labels.width() != width || labels.height() != height) {
      throw IoError(path + ": segmentation image is " + std::to_string(labels.width()) + "x" +
                    std::to_string(labels.height()) + " but the image is " + std::to_string(width) +
                    "x" + std::to_string(height));
    }
    levels.push_back(std::move(labels));
  }
  return segmentsFromLabels(levels, paths);
}

}  // namespace octarc
