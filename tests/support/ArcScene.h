// Hand-made sky for the tests of whole searches (search/SearchRun.h) and batches
// (batch/BatchRun.h): unit Gaussian noise of a fixed seed, no sky level, and objects drawn from
// closed forms, so that which of them a search must find follows from the drawing:
//
//   - a round galaxy: a circular Gaussian (E_IMAGE ~ 0, never a candidate of elongationGrid());
//   - an arc: a ring segment about a centre, its cross-section a Gaussian of the radius;
//   - a bar: a straight, uncurved segment with the same cross-section.
//
// Arcs and bars drawn with a length of 20 pixels or more and a cross-section sigma of 1 pixel
// have E_IMAGE = (a^2 - b^2) / (a^2 + b^2) near 0.9; round galaxies near 0. The grid selects
// 0.5 <= E_IMAGE < 1, so arcs and bars are candidates and round galaxies are not. Positions are
// 0-based pixel indices here; the catalogs' are 1-based (x + 1).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>

#include "FitsHeaders.h"
#include "octarc/core/Image.h"
#include "octarc/io/FitsImage.h"
#include "octarc/search/SearchKeys.h"
#include "octarc/selection/GridFile.h"

namespace octarc::test {

// Unit Gaussian noise of a fixed seed on a width x height image.
inline ImageF noiseImage(std::int64_t widthPix, std::int64_t heightPix, std::uint64_t seed) {
  ImageF image(widthPix, heightPix);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::int64_t y = 0; y < heightPix; ++y) {
    for (std::int64_t x = 0; x < widthPix; ++x) image(x, y) = float(noise(rng));
  }
  return image;
}

// A circular Gaussian of `peakAdu` centred on (x0Pix, y0Pix), added.
inline void addRoundGalaxy(ImageF& image, double x0Pix, double y0Pix, double sigmaPix,
                           double peakAdu) {
  for (std::int64_t y = 0; y < image.height(); ++y) {
    for (std::int64_t x = 0; x < image.width(); ++x) {
      const double r2 = std::pow(double(x) - x0Pix, 2) + std::pow(double(y) - y0Pix, 2);
      image(x, y) += float(peakAdu * std::exp(-0.5 * r2 / (sigmaPix * sigmaPix)));
    }
  }
}

// A ring segment about (xcPix, ycPix) of radius radiusPix, spanning directionDeg +-
// halfOpeningDeg (counter-clockwise from +x), its cross-section peakAdu exp(-d^2 / 2 sigma^2) of
// the distance d to the ring; added.
inline void addArc(ImageF& image, double xcPix, double ycPix, double radiusPix, double directionDeg,
                   double halfOpeningDeg, double sigmaPix, double peakAdu) {
  const double kDeg = std::numbers::pi / 180.0;
  for (std::int64_t y = 0; y < image.height(); ++y) {
    for (std::int64_t x = 0; x < image.width(); ++x) {
      const double dx = double(x) - xcPix, dy = double(y) - ycPix;
      // The angle from the arc's direction, in (-180, 180].
      const double offDeg = std::remainder(std::atan2(dy, dx) / kDeg - directionDeg, 360.0);
      if (std::fabs(offDeg) > halfOpeningDeg) continue;
      const double d = std::hypot(dx, dy) - radiusPix;
      image(x, y) += float(peakAdu * std::exp(-0.5 * d * d / (sigmaPix * sigmaPix)));
    }
  }
}

// A straight segment centred on (x0Pix, y0Pix), lengthPix long at angleDeg from +x, with the
// arc's cross-section; added.
inline void addBar(ImageF& image, double x0Pix, double y0Pix, double lengthPix, double angleDeg,
                   double sigmaPix, double peakAdu) {
  const double c = std::cos(angleDeg * std::numbers::pi / 180.0),
               s = std::sin(angleDeg * std::numbers::pi / 180.0);
  for (std::int64_t y = 0; y < image.height(); ++y) {
    for (std::int64_t x = 0; x < image.width(); ++x) {
      const double dx = double(x) - x0Pix, dy = double(y) - y0Pix;
      if (std::fabs(dx * c + dy * s) > 0.5 * lengthPix) continue;
      const double d = -dx * s + dy * c;
      image(x, y) += float(peakAdu * std::exp(-0.5 * d * d / (sigmaPix * sigmaPix)));
    }
  }
}

// The header of a north-up TAN image: sky position (raDeg, decDeg) at the 1-based reference
// pixel (crpix1, crpix2), scaleArcsec per pixel, RA growing to -x.
inline FitsHeader tanImageHeader(std::int64_t widthPix, std::int64_t heightPix, double crpix1,
                                 double crpix2, double raDeg, double decDeg, double scaleArcsec) {
  auto number = [](double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.12g", v);
    return std::string(text);
  };
  return imageHeader(int(widthPix), int(heightPix),
                     {{"CTYPE1", "'RA---TAN'"},
                      {"CTYPE2", "'DEC--TAN'"},
                      {"CRPIX1", number(crpix1)},
                      {"CRPIX2", number(crpix2)},
                      {"CRVAL1", number(raDeg)},
                      {"CRVAL2", number(decDeg)},
                      {"CD1_1", number(-scaleArcsec / 3600.0)},
                      {"CD2_2", number(scaleArcsec / 3600.0)},
                      {"RADESYS", "'ICRS'"}});
}

// Writes `image` with `header` (a single primary HDU) and returns the path.
inline std::string writeSceneImage(const std::filesystem::path& path, const ImageF& image,
                                   const FitsHeader& header) {
  writeImageFile(path.string(), {{header, &image, nullptr}});
  return path.string();
}

// A one-bin grid on 0.5 <= E_IMAGE < 1, written at `path`: its one bin holds every simulated
// arc, so the contour at P = 0.9 selects exactly the rows of that E_IMAGE.
inline std::string writeElongationGrid(const std::filesystem::path& path) {
  GridBinning binning({GridAxis{"E_IMAGE", 0.5, 1.0, 1}});
  OccupationGrid grid = OccupationGrid::fromCounts(binning, {{0, 10}}, 0, 0);
  const Contour contour = grid.contour(0.9);
  saveGrid(path.string(), SavedGrid{std::move(grid), contour, GridProvenance{}});
  return path.string();
}

// The search of a scene image: the shipped octarc.param, no sky to subtract (BACK_TYPE MANUAL),
// one level at 5 sigma without a filter (unit noise then makes no detection of its own), the
// default S/N floor (40) and RESOLVED_MIN (1"), one thread.
inline SearchRunSettings sceneSearchSettings(const std::string& imagePath,
                                             const std::string& gridPath,
                                             const std::string& outputDir) {
  SearchRunSettings s;
  s.run.imagePaths = {imagePath};
  s.run.parametersPath = std::string(OCTARC_SOURCE_DIR) + "/params/octarc.param";
  s.run.backgroundType = BackgroundType::Manual;
  s.run.filter = false;
  s.run.detectThreshold = 5.0;
  s.run.analysisThreshold = 5.0;
  s.run.threads = 1;
  s.gridPath = gridPath;
  s.outputDir = outputDir;
  return s;
}

}  // namespace octarc::test
