// Small FITS and source-extractor utilities for the detection tests (cfitsio directly, so the
// tests depend on nothing but the detection stage).
#pragma once

#include <fitsio.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>

#include "octarc/core/Image.h"

namespace octarc::test {

inline void checkFits(int status, const std::string& what) {
  if (status != 0) {
    char text[FLEN_STATUS];
    fits_get_errstatus(status, text);
    FAIL() << what << ": cfitsio " << text;
  }
}

inline void writeFloatFits(const std::filesystem::path& path, const ImageF& image) {
  std::filesystem::remove(path);
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {static_cast<long>(image.width()), static_cast<long>(image.height())};
  fits_create_file(&f, path.c_str(), &status);
  fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
  fits_write_img(f, TFLOAT, 1, image.size(), const_cast<float*>(image.data()), &status);
  fits_close_file(f, &status);
  checkFits(status, path.string());
}

inline void writeIntFits(const std::filesystem::path& path, const ImageI32& image) {
  std::filesystem::remove(path);
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {static_cast<long>(image.width()), static_cast<long>(image.height())};
  fits_create_file(&f, path.c_str(), &status);
  fits_create_img(f, LONG_IMG, 2, naxes, &status);
  fits_write_img(f, TINT, 1, image.size(), const_cast<std::int32_t*>(image.data()), &status);
  fits_close_file(f, &status);
  checkFits(status, path.string());
}

template <typename T>
Image<T> readFits(const std::filesystem::path& path) {
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {0, 0};
  int naxis = 0;
  fits_open_image(&f, path.c_str(), READONLY, &status);
  fits_get_img_dim(f, &naxis, &status);
  fits_get_img_size(f, 2, naxes, &status);
  Image<T> image(naxes[0], naxes[1]);
  constexpr int type = sizeof(T) == 4 && std::is_floating_point_v<T> ? TFLOAT : TINT;
  int anyNull = 0;
  fits_read_img(f, type, 1, image.size(), nullptr, image.data(), &anyNull, &status);
  fits_close_file(f, &status);
  checkFits(status, path.string());
  return image;
}

inline bool haveSourceExtractor() {
  return std::system("source-extractor -v > /dev/null 2>&1") == 0;
}

// Runs source-extractor on `image` in `dir` with SExtractor's built-in defaults (-dd) overridden
// by `options`; the catalog is not written. Returns the exit status.
inline int runSourceExtractor(const std::filesystem::path& dir, const std::string& image,
                              const std::string& options) {
  const std::string cmd = "cd '" + dir.string() + "' && source-extractor -dd > default.sex && " +
                          "source-extractor " + image +
                          " -c default.sex -CATALOG_TYPE NONE"
                          " -PARAMETERS_NAME /usr/share/source-extractor/default.param"
                          " -VERBOSE_TYPE QUIET " +
                          options + " > se.log 2>&1";
  return std::system(cmd.c_str());
}

#define OCTARC_REQUIRE_SOURCE_EXTRACTOR() \
  if (!::octarc::test::haveSourceExtractor()) GTEST_SKIP() << "source-extractor not found"

}  // namespace octarc::test
