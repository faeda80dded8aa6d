// The part of an image that a search covers: the DS9 region rule (io/Ds9Region.h), minus the
// pixels a weight map marks bad, minus a border margin. Its area is the denominator of every
// per-deg2 figure of a search.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/io/Ds9Region.h"
#include "octarc/io/Wcs.h"

namespace octarc {

struct SearchMaskSettings {
  std::vector<RegionShape> regions;  // none: the whole image
  // Pixels whose variance is +Inf (or NaN) are masked: the variance map of a prepared image, where
  // the weight threshold (WEIGHT_THRESH) has already marked bad pixels so. Null: none is masked.
  const ImageF* varianceAdu2 = nullptr;
  int borderPix = 0;  // pixels this close to an edge are masked (0: none)
};

class SearchMask {
 public:
  // Throws ConfigError for a negative border or a variance map of another size.
  SearchMask(std::int64_t width, std::int64_t height, const SearchMaskSettings& settings);

  std::int64_t width() const { return searched_.width(); }
  std::int64_t height() const { return searched_.height(); }
  // Whether the pixel holding the 1-based position is searched (false outside the image).
  bool searched(double xFits, double yFits) const;
  // The same for 0-based pixel indices.
  bool searchedPixel(std::int64_t x, std::int64_t y) const { return searched_(x, y) != 0; }
  std::int64_t searchedPixelCount() const { return searchedCount_; }
  // The searched area on the sky, in square degrees: each block of pixels weighted by the pixel
  // area of the WCS at its centre (the Jacobian determinant). Throws ConfigError where the WCS
  // gives no area for a block holding searched pixels.
  double searchedAreaDeg2(const Wcs& wcs) const;
  // Searched pixels per block of kAreaBlockPix x kAreaBlockPix pixels (the last row and column
  // of blocks may be cut by the image's edge), counted with the mask: the searched area at
  // block resolution, as a batch keeps it for the union of overlapping tiles.
  const Image<std::int32_t>& blockCounts() const { return blockCounts_; }

  static constexpr std::int64_t kAreaBlockPix = 64;

 private:
  Image<std::uint8_t> searched_;
  Image<std::int32_t> blockCounts_;
  std::int64_t searchedCount_ = 0;
};

// The area of searched pixels counted per block (SearchMask::blockCounts), each block weighted
// by the pixel area of the WCS at its centre, and by share(bx, by) when given (the part of block
// (bx, by) to count: a batch's union leaves out what an earlier tile searched). ConfigError
// where the WCS gives no area for a block holding searched pixels.
double searchedAreaDeg2(const Image<std::int32_t>& blockCounts, std::int64_t blockPix,
                        std::int64_t width, std::int64_t height, const Wcs& wcs,
                        const std::function<double(std::int64_t, std::int64_t)>& share = {});

// The 1-based pixel coordinate of the centre of block `block` along an axis of `size` pixels.
double blockCentreFits(std::int64_t block, std::int64_t blockPix, std::int64_t size);

}  // namespace octarc
