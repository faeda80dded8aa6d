// FITS files and shell commands for tests. Images are read and written with cfitsio directly, so
// that a stage's tests depend on nothing but that stage.
#pragma once

#include <fitsio.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "octarc/core/Image.h"

namespace octarc::test {

inline void checkFits(int status, const std::string& what) {
  if (status != 0) {
    char text[FLEN_STATUS];
    fits_get_errstatus(status, text);
    throw std::runtime_error(what + ": cfitsio: " + text);
  }
}

// Writes `image` as the primary HDU of a new file (float: BITPIX -32, int32: BITPIX 32).
template <typename T>
void writeFits(const std::filesystem::path& path, const Image<T>& image) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, std::int32_t>);
  constexpr bool isFloat = std::is_same_v<T, float>;
  std::filesystem::remove(path);
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {static_cast<long>(image.width()), static_cast<long>(image.height())};
  fits_create_file(&f, path.c_str(), &status);
  fits_create_img(f, isFloat ? FLOAT_IMG : LONG_IMG, 2, naxes, &status);
  fits_write_img(f, isFloat ? TFLOAT : TINT, 1, image.size(), const_cast<T*>(image.data()),
                 &status);
  fits_close_file(f, &status);
  checkFits(status, path.string());
}
inline void writeFloatFits(const std::filesystem::path& path, const ImageF& image) {
  writeFits(path, image);
}
inline void writeIntFits(const std::filesystem::path& path, const ImageI32& image) {
  writeFits(path, image);
}

// Reads the first image HDU (BSCALE/BZERO applied by cfitsio) as float or int32.
template <typename T>
Image<T> readFits(const std::filesystem::path& path) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, std::int32_t>);
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {0, 0};
  int naxis = 0;
  fits_open_image(&f, path.c_str(), READONLY, &status);
  checkFits(status, path.string());
  fits_get_img_dim(f, &naxis, &status);
  fits_get_img_size(f, 2, naxes, &status);
  Image<T> image(naxes[0], naxes[1]);
  int anyNull = 0;
  fits_read_img(f, std::is_same_v<T, float> ? TFLOAT : TINT, 1, image.size(), nullptr, image.data(),
                &anyNull, &status);
  fits_close_file(f, &status);
  checkFits(status, path.string());
  return image;
}

// Runs a shell command with its output discarded; returns its exit status.
inline int runQuiet(const std::string& command) {
  return std::system((command + " >/dev/null 2>&1").c_str());
}

inline bool haveProgram(const std::string& name) {
  return runQuiet("command -v " + name) == 0;
}

}  // namespace octarc::test
