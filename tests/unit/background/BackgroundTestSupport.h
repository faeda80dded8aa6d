// Helpers of the background tests (SExtractor runs, synthetic skies); the FITS basics are in
// tests/support/FitsTestFiles.h.
#pragma once

#include <fitsio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "FitsTestFiles.h"
#include "TestCommands.h"
#include "octarc/core/Image.h"

namespace octarc::test {

// Reads the first image HDU the way SExtractor does: integer pixels are scaled in float,
// (float)raw * (float)BSCALE + (float)BZERO, where cfitsio computes in double. The two differ by
// about one float ulp when BSCALE is not 1, which is enough to move a mesh's histogram mode.
inline ImageF readFitsAsSExtractor(const std::filesystem::path& path) {
  fitsfile* f = nullptr;
  int status = 0;
  fits_open_image(&f, path.c_str(), READONLY, &status);
  checkFits(status, path.string());
  int bitpix = 0;
  fits_get_img_type(f, &bitpix, &status);
  checkFits(status, path.string());
  if (bitpix < 0) {
    fits_close_file(f, &status);
    return readFits<float>(path);
  }
  long naxes[2] = {0, 0};
  fits_get_img_size(f, 2, naxes, &status);
  double bscale = 1.0, bzero = 0.0;
  int keyStatus = 0;
  fits_read_key(f, TDOUBLE, "BSCALE", &bscale, nullptr, &keyStatus);
  keyStatus = 0;
  fits_read_key(f, TDOUBLE, "BZERO", &bzero, nullptr, &keyStatus);
  fits_set_bscale(f, 1.0, 0.0, &status);
  std::vector<double> raw(static_cast<std::size_t>(naxes[0] * naxes[1]));
  double nulval = 0.0;
  int anynul = 0;
  fits_read_img(f, TDOUBLE, 1, static_cast<LONGLONG>(raw.size()), &nulval, raw.data(), &anynul,
                &status);
  fits_close_file(f, &status);
  checkFits(status, path.string());
  ImageF image(naxes[0], naxes[1]);
  const float bs = static_cast<float>(bscale), bz = static_cast<float>(bzero);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const float product = static_cast<float>(raw[i]) * bs;  // no fused multiply-add
    image[static_cast<std::int64_t>(i)] = product + bz;
  }
  return image;
}

// Value of a numeric card (e.g. SEXBKDEV) stored in a FITS_LDAC catalog's LDAC_IMHEAD cell.
inline double ldacHeaderValue(const std::filesystem::path& path, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string padded = key;
  padded.resize(8, ' ');
  padded += "=";
  const auto pos = bytes.find(padded);
  if (pos == std::string::npos) throw std::runtime_error(path.string() + ": no " + key);
  return std::stod(bytes.substr(pos + 9, 21));
}

// Runs source-extractor on `image` with the AUTO background and writes the named check images
// (types and names as comma lists) plus an LDAC catalog `catalog` in `dir`.
inline void runSExtractorBackground(const std::filesystem::path& image,
                                    const std::filesystem::path& dir, const std::string& extraArgs,
                                    const std::string& checkTypes, const std::string& checkNames,
                                    const std::string& catalog = "cat.ldac") {
  {
    std::ofstream param(dir / "bg.param");
    param << "NUMBER\n";
  }
  const std::string cmd = "cd '" + dir.string() + "' && source-extractor '" + image.string() +
                          "' -PARAMETERS_NAME bg.param -FILTER N -BACK_TYPE AUTO " + extraArgs +
                          " -CHECKIMAGE_TYPE " + checkTypes + " -CHECKIMAGE_NAME " + checkNames +
                          " -CATALOG_TYPE FITS_LDAC -CATALOG_NAME " + catalog;
  ASSERT_EQ(runQuiet(cmd), 0) << cmd;
}

// Largest |a - b| over all pixels.
inline double maxAbsDiff(const ImageF& a, const ImageF& b) {
  double worst = 0.0;
  for (std::int64_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, std::fabs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
  return worst;
}

// Sky plane + Gaussian noise (seeded): the truth of the background test.
inline ImageF skyWithGradient(std::int64_t w, std::int64_t h, double sky, double gx, double gy,
                              double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  ImageF image(w, h);
  for (std::int64_t y = 0; y < h; ++y)
    for (std::int64_t x = 0; x < w; ++x)
      image(x, y) = static_cast<float>(sky + gx * x + gy * y + noise(rng));
  return image;
}

// Adds round Gaussian sources of random position, width 1-3 px and peak up to peakMax.
inline void addSources(ImageF& image, int count, double peakMax, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(0.0, static_cast<double>(image.width()));
  std::uniform_real_distribution<double> uy(0.0, static_cast<double>(image.height()));
  std::uniform_real_distribution<double> us(1.0, 3.0);
  std::uniform_real_distribution<double> up(0.0, 1.0);
  for (int n = 0; n < count; ++n) {
    const double cx = ux(rng), cy = uy(rng), s = us(rng);
    const double peak = peakMax * std::pow(10.0, -2.0 * up(rng));
    const std::int64_t r = static_cast<std::int64_t>(std::ceil(5 * s));
    for (std::int64_t y = std::max<std::int64_t>(0, static_cast<std::int64_t>(cy) - r);
         y <= std::min(image.height() - 1, static_cast<std::int64_t>(cy) + r); ++y)
      for (std::int64_t x = std::max<std::int64_t>(0, static_cast<std::int64_t>(cx) - r);
           x <= std::min(image.width() - 1, static_cast<std::int64_t>(cx) + r); ++x) {
        const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        image(x, y) += static_cast<float>(peak * std::exp(-0.5 * d2 / (s * s)));
      }
  }
}

}  // namespace octarc::test
