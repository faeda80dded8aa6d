// A 2-D pixel array in memory. Indices are 0-based (x along NAXIS1, fastest varying; y along
// NAXIS2); see core/Conventions.h for how they map to SExtractor's 1-based coordinates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/UninitializedAllocator.h"

namespace octarc {

// width * height, refusing a negative side or a product whose pixels of `bytesPerPixel` bytes
// could not be addressed (more than PTRDIFF_MAX bytes), without ever overflowing. Readers check
// a file's sizes first and name the file; this is the guard of every Image.
inline std::int64_t checkedPixelCount(std::int64_t width, std::int64_t height,
                                      std::size_t bytesPerPixel) {
  std::int64_t count = 0;
  std::int64_t bytes = 0;
  if (width < 0 || height < 0 || __builtin_mul_overflow(width, height, &count) ||
      __builtin_mul_overflow(count, static_cast<std::int64_t>(bytesPerPixel), &bytes) ||
      bytes > PTRDIFF_MAX) {
    throw Error("image of " + std::to_string(width) + " x " + std::to_string(height) +
                " pixels cannot be held in memory");
  }
  return count;
}

// The longest image side octarc handles: the detector and pixel runs (core/Segment.h) hold
// coordinates as 32-bit integers.
inline constexpr std::int64_t kMaxImageSidePix = 2147483647;

// Tag for the Image constructor that leaves the pixels unset.
struct UninitializedPixels {};

template <typename T>
class Image {
 public:
  Image() = default;
  // Throws Error for a negative size or one whose pixels could not be addressed.
  Image(std::int64_t width, std::int64_t height, T fill = T{})
      : width_(width),
        height_(height),
        pixels_(static_cast<std::size_t>(checkedPixelCount(width, height, sizeof(T))), fill) {}
  // Pixels left unset, for a caller that writes every one of them.
  Image(std::int64_t width, std::int64_t height, UninitializedPixels)
      : width_(width),
        height_(height),
        pixels_(static_cast<std::size_t>(checkedPixelCount(width, height, sizeof(T)))) {}

  std::int64_t width() const { return width_; }
  std::int64_t height() const { return height_; }
  std::int64_t size() const { return width_ * height_; }
  bool empty() const { return pixels_.empty(); }

  // Linear index of pixel (x, y): y * width + x.
  std::int64_t index(std::int64_t x, std::int64_t y) const { return y * width_ + x; }

  T& operator()(std::int64_t x, std::int64_t y) { return pixels_[index(x, y)]; }
  const T& operator()(std::int64_t x, std::int64_t y) const { return pixels_[index(x, y)]; }
  T& operator[](std::int64_t i) { return pixels_[i]; }
  const T& operator[](std::int64_t i) const { return pixels_[i]; }

  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  using PixelVector = std::vector<T, UninitializedAllocator<T>>;
  PixelVector& pixels() { return pixels_; }
  const PixelVector& pixels() const { return pixels_; }

 private:
  std::int64_t width_ = 0;
  std::int64_t height_ = 0;
  PixelVector pixels_;
};

using ImageF = Image<float>;
using ImageD = Image<double>;
using ImageI32 = Image<std::int32_t>;

}  // namespace octarc
