#include "octarc/selection/SearchMask.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

// The 0-based pixel index range [first, last] of the pixels whose centres a shape's bounding
// box covers, clipped to the image; empty when first > last.
struct PixelRange {
  std::int64_t xFirst, xLast, yFirst, yLast;
};

PixelRange pixelRange(const RegionShape& shape, std::int64_t width, std::int64_t height) {
  const auto b = shape.bounds();
  const auto first = [](double fitsLo) {
    return static_cast<std::int64_t>(std::ceil(fromFitsPixel(fitsLo)));
  };
  const auto last = [](double fitsHi) {
    return static_cast<std::int64_t>(std::floor(fromFitsPixel(fitsHi)));
  };
  // Clip in double first: a huge shape must not overflow the integer conversion.
  const auto clip = [](double v, std::int64_t n) { return std::clamp(v, -1.0, double(n)); };
  return {first(clip(b[0], width)), last(clip(b[1], width)), first(clip(b[2], height)),
          last(clip(b[3], height))};
}

void paint(Image<std::uint8_t>& image, const RegionShape& shape, std::uint8_t value) {
  const PixelRange r = pixelRange(shape, image.width(), image.height());
  for (std::int64_t y = std::max<std::int64_t>(r.yFirst, 0);
       y <= std::min(r.yLast, image.height() - 1); ++y) {
    for (std::int64_t x = std::max<std::int64_t>(r.xFirst, 0);
         x <= std::min(r.xLast, image.width() - 1); ++x) {
      if (shape.contains(toFitsPixel(double(x)), toFitsPixel(double(y)))) image(x, y) = value;
    }
  }
}

}  // namespace

SearchMask::SearchMask(std::int64_t width, std::int64_t height, const SearchMaskSettings& settings)
    : searched_(width, height, 0),
      blockCounts_((width + kAreaBlockPix - 1) / kAreaBlockPix,
                   (height + kAreaBlockPix - 1) / kAreaBlockPix, 0) {
  if (settings.borderPix < 0) {
    throw ConfigError("border margin " + std::to_string(settings.borderPix) + " is negative");
  }
  const ImageF* variance = settings.varianceAdu2;
  if (variance != nullptr && (variance->width() != width || variance->height() != height)) {
    throw ConfigError("weight map is " + std::to_string(variance->width()) + "x" +
                      std::to_string(variance->height()) + " but the image is " +
                      std::to_string(width) + "x" + std::to_string(height));
  }
  // DS9's rule (regionContains), painted shape by shape inside each bounding box for speed: the
  // union of the include shapes (the whole image if none), then every exclude shape cut out.
  const bool anyInclude = std::any_of(settings.regions.begin(), settings.regions.end(),
                                      [](const RegionShape& s) { return !s.exclude; });
  if (!anyInclude) std::fill(searched_.pixels().begin(), searched_.pixels().end(), 1);
  for (const RegionShape& shape : settings.regions) {
    if (!shape.exclude) paint(searched_, shape, 1);
  }
  for (const RegionShape& shape : settings.regions) {
    if (shape.exclude) paint(searched_, shape, 0);
  }
  // One pass: the border, bad weights, and the counts (all, and per block for the area).
  const std::int64_t border = settings.borderPix;
  for (std::int64_t y = 0; y < height; ++y) {
    const bool rowInBorder = y < border || y >= height - border;
    std::int32_t* blockRow = width > 0 ? &blockCounts_(0, y / kAreaBlockPix) : nullptr;
    for (std::int64_t x = 0; x < width; ++x) {
      std::uint8_t& pixel = searched_(x, y);
      if (rowInBorder || x < border || x >= width - border) pixel = 0;
      // +Inf marks a bad weight; NaN (never made by prepareImage) is treated the same.
      if (variance != nullptr && !std::isfinite((*variance)(x, y))) pixel = 0;
      searchedCount_ += pixel;
      blockRow[x / kAreaBlockPix] += pixel;
    }
  }
}

bool SearchMask::searched(double xFits, double yFits) const {
  // Pixel i covers [i + 0.5, i + 1.5) in 1-based coordinates.
  const double x = std::floor(xFits - 0.5);
  const double y = std::floor(yFits - 0.5);
  if (!(x >= 0.0 && y >= 0.0 && x < double(width()) && y < double(height()))) return false;
  return searchedPixel(static_cast<std::int64_t>(x), static_cast<std::int64_t>(y));
}

double searchedAreaDeg2(const Image<std::int32_t>& blockCounts, std::int64_t blockPix,
                        std::int64_t width, std::int64_t height, const Wcs& wcs,
                        const std::function<double(std::int64_t, std::int64_t)>& share) {
  double areaDeg2 = 0.0;
  for (std::int64_t by = 0; by < blockCounts.height(); ++by) {
    for (std::int64_t bx = 0; bx < blockCounts.width(); ++bx) {
      const std::int32_t count = blockCounts(bx, by);
      if (count == 0) continue;
      const double fraction = share ? share(bx, by) : 1.0;
      if (fraction == 0.0) continue;
      const double xc = blockCentreFits(bx, blockPix, width);
      const double yc = blockCentreFits(by, blockPix, height);
      const double pixelAreaDeg2 = wcs.pixelAreaDeg2(xc, yc);
      if (!std::isfinite(pixelAreaDeg2)) {
        throw ConfigError("the WCS gives no pixel area at pixel (" + std::to_string(xc) + ", " +
                          std::to_string(yc) + ") of the searched area");
      }
      areaDeg2 += fraction * pixelAreaDeg2 * double(count);
    }
  }
  return areaDeg2;
}

double blockCentreFits(std::int64_t block, std::int64_t blockPix, std::int64_t size) {
  const std::int64_t first = block * blockPix;
  const std::int64_t last = std::min(first + blockPix, size) - 1;
  return toFitsPixel(0.5 * double(first + last));
}

double SearchMask::searchedAreaDeg2(const Wcs& wcs) const {
  return octarc::searchedAreaDeg2(blockCounts_, kAreaBlockPix, width(), height(), wcs);
}

}  // namespace octarc
