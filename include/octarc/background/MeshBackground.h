// SExtractor's AUTO background (BACK_TYPE AUTO): mesh statistics, median filtering of the mesh
// grid and bicubic-spline interpolation to every pixel, reproducing source-extractor 2.25
// (SEXTRACTOR.md §5) down to its float arithmetic, so that BACKGROUND / BACKGROUND_RMS check
// images and the global noise SEXBKDEV agree with SExtractor's.
//
// Algorithm, per mesh of meshWidth x meshHeight pixels (the meshes of the last column and row
// are narrower/shorter when the image size is not a multiple of the mesh size):
//   1. mean and standard deviation of the valid pixels; a mesh with fewer than half of its
//      pixels valid is "bad"; then mean and standard deviation of the pixels within
//      mean +- 2 sigma. When a mesh row holds more than 2^20 pixels, these two statistics use an
//      evenly spaced subset of its rows, as SExtractor does.
//   2. a histogram of the mesh pixels over mean +- 5 sigma and, from it, an iterative +-3 sigma
//      clipped estimate: level = 2.5 median - 1.5 mean when |mean - median| < 0.3 sigma, else
//      the median; rms = the clipped standard deviation.
//   3. bad meshes take the average of their nearest good meshes; the grid is median filtered
//      (filterWidth x filterHeight, window shrunk symmetrically at the grid edges) where the
//      median differs from the mesh value by at least filterThresholdAdu.
//   4. level and rms at every pixel: SExtractor's spline through the mesh centres (a cubic
//      spline along y through each mesh column, then along x through the interpolated nodes).
// The global level (SEXBKGND) and noise (SEXBKDEV) are the medians of the filtered mesh grids.
// Pixels that are NaN, infinite or <= -1e30 (SExtractor's blank value) are ignored.
//
// On the same pixel values the maps, SEXBKGND and SEXBKDEV are bit-identical to
// source-extractor 2.25's (tests/unit/background). Two things to know for that:
//   - SExtractor scales integer FITS pixels in float, (float)raw * (float)BSCALE +
//     (float)BZERO; cfitsio scales in double. Where BSCALE != 1 the two differ by one float ulp,
//     which can move a mesh's histogram mode by a fraction of the noise.
//   - Deliberate differences: +-Inf pixels are ignored (SExtractor lets +Inf spoil the mesh), and
//     with a 1-pixel-wide mesh the RMS row takes the node values directly like the level row
//     (SExtractor extrapolates its spline there).
//
// With a weight map (WEIGHT_TYPE MAP_WEIGHT / MAP_RMS / MAP_VAR, SEXTRACTOR.md §4) the map is
// turned into a variance per pixel (1/w, rms^2, var); pixels whose variance reaches the
// converted WEIGHT_THRESH are left out of the mesh statistics, the variance map gets its own
// mesh grid, and the weight scale (SEXDWSCL) is the median over meshes of mesh rms /
// sqrt(mesh variance). RESCALE_WEIGHTS Y multiplies the variances by its square
// (pixelVariance); N divides the global sigma by it instead.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "octarc/core/Image.h"

namespace octarc {

struct MeshBackgroundSettings {
  int meshWidth = 64;   // BACK_SIZE (first value), pixels
  int meshHeight = 64;  // BACK_SIZE (second value, or the first again), pixels
  int filterWidth = 3;  // BACK_FILTERSIZE, meshes
  int filterHeight = 3;
  double filterThresholdAdu = 0.0;  // BACK_FILTTHRESH (SExtractor spelling), ADU
  int threadCount = 0;              // 0 = all hardware threads; results never depend on it
};

enum class WeightMapType {
  Weight,    // MAP_WEIGHT: variance = scale^2 / w (w <= 0: 1e30, never used)
  Rms,       // MAP_RMS: variance = rms^2 (not rescaled)
  Variance,  // MAP_VAR: variance = scale^2 * var
};

struct WeightMap {
  const ImageF* pixels = nullptr;  // same size as the image; nullptr = no weight map
  WeightMapType type = WeightMapType::Weight;
  // WEIGHT_THRESH in the map's own units; unset = SExtractor's default (0 for MAP_WEIGHT, 1e30
  // for the others).
  std::optional<double> threshold;
  bool rescale = true;              // RESCALE_WEIGHTS
  std::string name = "weight map";  // starts error messages about the map
};

class MeshBackground {
 public:
  // Measures the background of `image`. `imageName` (usually the file name) starts the message
  // of any error. Throws ConfigError for a mesh or filter size < 1 and IoError for an empty
  // image or one without any valid pixel.
  static MeshBackground estimate(const ImageF& image, const MeshBackgroundSettings& settings,
                                 std::string_view imageName = "image");
  // The same with a weight map. Throws IoError if the map's size differs from the image's.
  static MeshBackground estimate(const ImageF& image, const MeshBackgroundSettings& settings,
                                 const WeightMap& weights, std::string_view imageName = "image");

  std::int64_t width() const { return width_; }
  std::int64_t height() const { return height_; }
  // Mesh size actually used (BACK_SIZE clipped to the image size, as SExtractor does).
  int meshWidth() const { return meshWidth_; }
  int meshHeight() const { return meshHeight_; }
  int meshCountX() const { return nx_; }
  int meshCountY() const { return ny_; }

  // SEXBKGND: median of the filtered mesh background grid.
  double globalLevelAdu() const { return globalLevelAdu_; }
  // SEXBKDEV: median of the filtered mesh RMS grid; 1 when the image is (mainly) constant.
  double globalSigmaAdu() const { return globalSigmaAdu_; }

  // Weight map results: the weight scale (SEXDWSCL; 1 without rescaling, for MAP_RMS or
  // without weights), the variance threshold, and a weight pixel turned into a variance (for
  // per-pixel thresholds DETECT_THRESH * sqrt(variance)).
  bool hasWeights() const { return hasWeights_; }
  double weightScale() const { return weightScale_; }
  float varianceThreshold() const { return varianceThreshold_; }
  float pixelVariance(float weightPixel) const;
  // Filtered mesh grid of the variance map's mode (empty without weights).
  const ImageF& meshVarianceLevels() const { return meshVariance_; }

  // Non-fatal problems, e.g. constant data ("sigma set to 1") or meshes without valid pixels.
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Interpolated background / RMS of row y (0 <= y < height) into out[0 .. width-1].
  void levelRow(std::int64_t y, float* out) const;
  void rmsRow(std::int64_t y, float* out) const;
  // Subtracts the interpolated background of row y from row[0 .. width-1] in place.
  void subtractRow(std::int64_t y, float* row) const;

  // Full-size maps (BACKGROUND and BACKGROUND_RMS check images).
  ImageF levelImage() const;
  ImageF rmsImage() const;
  // Mesh-resolution maps after filtering (MINIBACKGROUND and MINIBACK_RMS check images).
  const ImageF& meshLevels() const { return meshLevel_; }
  const ImageF& meshRms() const { return meshRms_; }

 private:
  // Writes the interpolated row into out, or subtracts it from out when `subtract`.
  void interpolateRow(const ImageF& grid, const std::vector<float>& d2y, std::int64_t y, float* out,
                      bool subtract) const;
  void fillImage(ImageF& out, bool isLevel) const;
  // The global noise from the filtered mesh RMS grid (its median, with SExtractor's fallbacks).
  float medianMeshSigma(const std::string& imageName);
  // The weight scale (or the global sigma) from the mesh statistics of the weight map.
  void scaleWeights(const ImageF& weightLevel, const ImageF& weightRms,
                    const std::vector<unsigned char>& bad, std::size_t goodCount,
                    const MeshBackgroundSettings& settings, const WeightMap& weights, float sigma);
  // The per-column interpolation coefficients along x (xRuns_, xDx_, ...).
  void buildColumnWalk();

  std::int64_t width_ = 0;
  std::int64_t height_ = 0;
  int meshWidth_ = 0;
  int meshHeight_ = 0;
  int nx_ = 0;
  int ny_ = 0;
  int threadCount_ = 1;
  double globalLevelAdu_ = 0.0;
  double globalSigmaAdu_ = 1.0;
  bool hasWeights_ = false;
  WeightMapType weightType_ = WeightMapType::Weight;
  double weightScale_ = 1.0;
  float varianceThreshold_ = 0.0f;
  ImageF meshVariance_;
  std::vector<std::string> warnings_;
  ImageF meshLevel_;             // filtered mesh background, nx x ny
  ImageF meshRms_;               // filtered mesh RMS, nx x ny
  std::vector<float> levelD2y_;  // spline second derivatives along y (SExtractor's scaling)
  std::vector<float> rmsD2y_;
  // Per-column interpolation coefficients along x (they do not depend on the row).
  // Columns [begin, end) interpolate between nodes `node` and `node + 1`; the runs are
  // contiguous and in increasing order.
  struct XRun {
    std::int64_t begin, end;
    int node;
  };
  std::vector<XRun> xRuns_;
  std::vector<float> xDx_, xCdx_, xDx3_, xCdx3_;
};

}  // namespace octarc
