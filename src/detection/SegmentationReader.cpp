#include "octarc/detection/SegmentationReader.h"

#include <algorithm>
#include <cstddef>
#include <string>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

std::string sizeText(std::int64_t width, std::int64_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// "FITS pixel (x, y)" with SExtractor's 1-based coordinates, for error messages.
std::string pixelText(std::int64_t index, std::int64_t width) {
  return "FITS pixel (" + std::to_string(index % width + 1) + ", " +
         std::to_string(index / width + 1) + ")";
}

// Maps each distinct label of one level to a dense slot 0, 1, ... in ascending label order.
// A direct table when the labels are small (the normal case: SExtractor numbers objects 1..N);
// a sorted list with binary search for files with huge, sparse label values.
class LabelSlots {
 public:
  LabelSlots(const ImageI32& labels, const std::string& name) {
    const std::int32_t* px = labels.data();
    const std::int64_t n = labels.size();
    std::int32_t maxLabel = 0;
    for (std::int64_t i = 0; i < n; ++i) {
      if (px[i] < 0) {
        throw IoError(name + ": negative label " + std::to_string(px[i]) + " at " +
                      pixelText(i, labels.width()) + " of a segmentation image");
      }
      maxLabel = std::max(maxLabel, px[i]);
    }
    dense_ = maxLabel <= std::max<std::int64_t>(n, 1 << 20);
    if (dense_) {
      table_.assign(static_cast<std::size_t>(maxLabel) + 1, -1);
      for (std::int64_t i = 0; i < n; ++i) table_[px[i]] = 0;
      for (std::int32_t label = 1; label <= maxLabel; ++label) {
        if (table_[label] == 0) {
          table_[label] = static_cast<std::int32_t>(labelsInOrder_.size());
          labelsInOrder_.push_back(label);
        }
      }
    } else {
      for (std::int64_t i = 0; i < n; ++i) {
        if (px[i] > 0) labelsInOrder_.push_back(px[i]);
      }
      std::sort(labelsInOrder_.begin(), labelsInOrder_.end());
      labelsInOrder_.erase(std::unique(labelsInOrder_.begin(), labelsInOrder_.end()),
                           labelsInOrder_.end());
    }
  }

  std::size_t count() const { return labelsInOrder_.size(); }
  std::int32_t label(std::size_t slot) const { return labelsInOrder_[slot]; }

  // Slot of a label > 0 that occurs in the image.
  std::int32_t slot(std::int32_t label) const {
    if (dense_) return table_[label];
    return static_cast<std::int32_t>(
        std::lower_bound(labelsInOrder_.begin(), labelsInOrder_.end(), label) -
        labelsInOrder_.begin());
  }

 private:
  bool dense_ = true;
  std::vector<std::int32_t> table_;
  std::vector<std::int32_t> labelsInOrder_;
};

}  // namespace

std::vector<Segment> segmentsFromLabels(const std::vector<ImageI32>& levels,
                                        const std::vector<std::string>& names) {
  if (names.size() != levels.size()) {
    throw ConfigError("segmentation: " + std::to_string(levels.size()) + " label images but " +
                      std::to_string(names.size()) + " names");
  }
  std::vector<Segment> segments;
  if (levels.empty()) return segments;

  const std::int64_t width = levels[0].width();
  const std::int64_t height = levels[0].height();
  for (std::size_t k = 1; k < levels.size(); ++k) {
    if (levels[k].width() != width || levels[k].height() != height) {
      throw IoError(names[k] + ": segmentation image is " +
                    sizeText(levels[k].width(), levels[k].height()) + " but " + names[0] + " is " +
                    sizeText(width, height));
    }
  }

  const std::int64_t n = width * height;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const std::int32_t* px = levels[k].data();
    const LabelSlots slots(levels[k], names[k]);
    const std::size_t firstSegment = segments.size();
    segments.resize(firstSegment + slots.count());

    // One bucket pass: count pixels per label, then fill the lists in ascending pixel order.
    std::vector<std::int64_t> counts(slots.count(), 0);
    for (std::int64_t i = 0; i < n; ++i) {
      if (px[i] > 0) ++counts[slots.slot(px[i])];
    }
    for (std::size_t s = 0; s < slots.count(); ++s) {
      Segment& seg = segments[firstSegment + s];
      seg.number = slots.label(s);
      seg.level = static_cast<int>(k) + 1;
      seg.pixels.reserve(static_cast<std::size_t>(counts[s]));
    }

    // parent[s]: the label of level k - 1 under label s so far (-1 = none seen yet).
    std::vector<std::int32_t> parent(k > 0 ? slots.count() : 0, -1);
    const std::int32_t* below = k > 0 ? levels[k - 1].data() : nullptr;
    for (std::int64_t i = 0; i < n; ++i) {
      if (px[i] <= 0) continue;
      const std::int32_t s = slots.slot(px[i]);
      segments[firstSegment + s].pixels.push_back(i);
      if (below == nullptr) continue;
      const std::int32_t under = below[i];
      if (under == 0) {
        throw IoError(
            names[k] + ": label " + std::to_string(px[i]) + " at level " + std::to_string(k + 1) +
            " has " + pixelText(i, width) + " on the background of level " + std::to_string(k) +
            " (" + names[k - 1] +
            "); the levels do not nest (give SEGMENTATION_NAME and DETECT_LEVELS lowest threshold "
            "first)");
      }
      if (parent[s] < 0) {
        parent[s] = under;
      } else if (parent[s] != under) {
        throw IoError(
            names[k] + ": label " + std::to_string(px[i]) + " at level " + std::to_string(k + 1) +
            " lies in labels " + std::to_string(parent[s]) + " and " + std::to_string(under) +
            " of level " + std::to_string(k) + " (" + names[k - 1] +
            "); the levels do not nest (give SEGMENTATION_NAME and DETECT_LEVELS lowest threshold "
            "first)");
      }
    }
    for (std::size_t s = 0; s < parent.size(); ++s) {
      segments[firstSegment + s].parentNumber = parent[s];
    }
  }
  return segments;
}

}  // namespace octarc
