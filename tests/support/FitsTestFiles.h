// FITS files for tests, read and written with cfitsio directly, so that a stage's tests depend on
// nothing but that stage: images, small files built HDU by HDU, and files written byte by byte.
#pragma once

#include <fitsio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

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

// A double value of row `row` (1-based) of column `column` of the first extension's table.
inline double tableValue(const std::string& path, const char* column, long row) {
  fitsfile* f = nullptr;
  int status = 0;
  fits_open_file(&f, (path + "[1]").c_str(), READONLY, &status);
  int col = 0;
  fits_get_colnum(f, CASEINSEN, const_cast<char*>(column), &col, &status);
  double v = NAN;
  int anyNull = 0;
  fits_read_col(f, TDOUBLE, col, row, 1, 1, nullptr, &v, &anyNull, &status);
  fits_close_file(f, &status);
  EXPECT_EQ(status, 0) << column;
  return v;
}

// A FITS file under construction; each call appends one HDU (the first is the primary).
class FitsWriter {
 public:
  explicit FitsWriter(const std::filesystem::path& path) : path_(path.string()) {
    std::filesystem::remove(path);
    fits_create_file(&f_, path_.c_str(), &status_);
    check("create");
  }
  ~FitsWriter() {
    if (f_ != nullptr) close();
  }
  void close() {
    fits_close_file(f_, &status_);
    f_ = nullptr;
    check("close");
  }

  // An image HDU holding the raw stored values (no scaling applied by cfitsio), plus cards.
  FitsWriter& image(int bitpix, std::vector<long> naxes, const std::vector<double>& raw,
                    const std::vector<std::string>& cards = {}) {
    fits_create_img(f_, bitpix, static_cast<int>(naxes.size()), naxes.data(), &status_);
    check("create_img");
    for (const std::string& card : cards) {
      fits_write_record(f_, card.c_str(), &status_);
      check("write_record " + card);
    }
    if (!raw.empty()) {
      // The BSCALE/BZERO cards written above are for the reader; store raw values unchanged.
      fits_set_bscale(f_, 1.0, 0.0, &status_);
      if (bitpix > 0) fits_set_imgnull(f_, 0, &status_);
      check("set_bscale");
      std::vector<double> copy = raw;
      fits_write_img(f_, TDOUBLE, 1, static_cast<LONGLONG>(copy.size()), copy.data(), &status_);
      check("write_img");
    }
    return *this;
  }
  FitsWriter& emptyPrimary() { return image(8, {}, {}); }
  // A one-column binary table HDU.
  FitsWriter& table(const std::string& extname) {
    char ttype[] = "NUMBER";
    char tform[] = "1J";
    char* types[] = {ttype};
    char* forms[] = {tform};
    fits_create_tbl(f_, BINARY_TBL, 0, 1, types, forms, nullptr, extname.c_str(), &status_);
    check("create_tbl");
    return *this;
  }

 private:
  void check(const std::string& what) {
    if (status_ != 0) {
      char text[FLEN_STATUS];
      fits_get_errstatus(status_, text);
      ADD_FAILURE() << path_ << ": " << what << ": " << text;
      status_ = 0;
    }
  }
  std::string path_;
  fitsfile* f_ = nullptr;
  int status_ = 0;
};

// A header card "KEY     = value" padded to 80 characters.
inline std::string card(const std::string& key, const std::string& value) {
  std::string c = key;
  c.resize(8, ' ');
  c += "= " + value;
  c.resize(80, ' ');
  return c;
}

// A FITS file written byte by byte, for headers that cfitsio refuses to write (sizes larger than
// the file, broken keywords): each HDU is its cards (padded to 80 characters, END added, blocks
// of 2880) followed by `dataBytes` zero bytes padded to a full block.
struct RawHdu {
  std::vector<std::string> cards;
  std::size_t dataBytes = 0;
};
inline void writeRawFits(const std::filesystem::path& path, const std::vector<RawHdu>& hdus) {
  std::string bytes;
  for (const RawHdu& hdu : hdus) {
    for (std::string c : hdu.cards) {
      c.resize(80, ' ');
      bytes += c;
    }
    bytes += std::string("END").append(77, ' ');
    bytes.append((2880 - bytes.size() % 2880) % 2880, ' ');
    bytes.append(hdu.dataBytes, '\0');
    bytes.append((2880 - bytes.size() % 2880) % 2880, '\0');
  }
  std::ofstream(path, std::ios::binary) << bytes;
}

// The cards of a primary image header of the given BITPIX and axes, then `extra`.
inline std::vector<std::string> primaryCards(int bitpix, const std::vector<std::string>& axes,
                                             const std::vector<std::string>& extra = {}) {
  std::vector<std::string> cards = {card("SIMPLE", "T"), card("BITPIX", std::to_string(bitpix)),
                                    card("NAXIS", std::to_string(axes.size()))};
  for (std::size_t k = 0; k < axes.size(); ++k) {
    cards.push_back(card("NAXIS" + std::to_string(k + 1), axes[k]));
  }
  cards.insert(cards.end(), extra.begin(), extra.end());
  return cards;
}

}  // namespace octarc::test
