#include "octarc/run/PreparedImage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <thread>

#include "octarc/background/GlobalBackground.h"
#include "octarc/background/MeshBackground.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/Filter.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/ConvFile.h"

namespace octarc {

namespace {

// Median of the finite values of an image (for the global sigma of an RMS check-image, the
// way SExtractor takes the median of its mesh RMS map).
double finiteMedian(const ImageF& image) {
  std::vector<float> values;
  values.reserve(std::size_t(image.size()));
  for (float v : image.pixels()) {
    if (std::isfinite(v)) values.push_back(v);
  }
  if (values.empty()) return std::nan("");
  auto mid = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// A map of the image's size: IoError naming it (`name`) otherwise.
ImageF checkMapLike(ImageF map, const std::string& name, const ImageHdu& image, const char* what) {
  if (map.width() != image.pixels.width() || map.height() != image.pixels.height()) {
    throw IoError(name + ": " + what + " is " + std::to_string(map.width()) + "x" +
                  std::to_string(map.height()) + " but the image is " +
                  std::to_string(image.pixels.width()) + "x" +
                  std::to_string(image.pixels.height()));
  }
  return map;
}

ImageF readMapLike(const std::string& path, const ImageHdu& image, const char* what) {
  return checkMapLike(std::move(readImage(path).pixels), path, image, what);
}

void subtractMap(ImageF& image, const ImageF& background) {
  float* p = image.data();
  const float* b = background.data();
  for (std::int64_t i = 0; i < image.size(); ++i) p[i] -= b[i];
}

void subtractConstant(ImageF& image, double level) {
  const float value = float(level);
  for (float& p : image.pixels()) p -= value;
}

// Weight-map pixels to variances (ADU^2), in place. WEIGHT_THRESH is in the map's own units:
// weights at or below it, or RMS / variance values at or above it, are bad pixels (+Inf).
void weightsToVariance(ImageF& weights, const MeshBackground& mesh, const RunSettings& settings) {
  const bool isWeight = settings.weightType == WeightType::MapWeight;
  const float threshold = float(settings.weightThreshold.value_or(isWeight ? 0.0 : 1e30));
  constexpr float inf = std::numeric_limits<float>::infinity();
  for (float& w : weights.pixels()) {
    const bool good = isWeight ? w > threshold : w < threshold;
    w = good ? mesh.pixelVariance(w) : inf;
  }
}

}  // namespace

CatalogRunValues catalogRunValues(const InputCatalogPart& part, const std::string& catalogPath) {
  const FitsHeader& imhead = part.imageHeader;
  const auto read = [&](const char* key, const char* range,
                        bool (*inRange)(double)) -> std::optional<double> {
    const std::optional<std::string> text = imhead.value(key);
    if (!text) return std::nullopt;
    const std::optional<double> v = imhead.number(key);
    if (!v || !inRange(*v)) {
      throw IoError(catalogPath + ": LDAC_IMHEAD for the objects table in HDU " +
                    std::to_string(part.objectsHdu - 1) + ": " + key + " = " +
                    quoteForMessage(*text) + " is not " + range);
    }
    return v;
  };
  CatalogRunValues v;
  v.backgroundAdu = read("SEXBKGND", "a finite number", [](double) { return true; });
  v.sigmaAdu = read("SEXBKDEV", "a finite number > 0", [](double x) { return x > 0; });
  v.gain = read("SEXGAIN", "a finite number >= 0", [](double x) { return x >= 0; });
  v.thresholdAdu = read("SEXTHLD", "a finite number > 0", [](double x) { return x > 0; });
  v.analysisThresholdAdu = read("SEXATHLD", "a finite number > 0", [](double x) { return x > 0; });
  return v;
}

std::optional<double> headerNonNegative(const FitsHeader& header, const std::string& key,
                                        const std::string& imagePath, const std::string& instead,
                                        std::vector<std::string>& warnings) {
  const std::optional<std::string> text = header.value(key);
  if (!text) return std::nullopt;
  const std::optional<double> v = header.number(key);
  if (v && *v >= 0) return v;
  warnings.push_back(imagePath + ": header " + key + " = " + quoteForMessage(*text) +
                     " is not a finite number >= 0: ignored, using " + instead + " instead");
  return std::nullopt;
}

std::string extensionPath(const std::string& path, int e, int count, const char* what) {
  if (count == 1) return path;
  const std::vector<std::string> hdus = listImageHdus(path);
  if (int(hdus.size()) != count) {
    throw IoError(path + ": " + what + " has " + std::to_string(hdus.size()) +
                  " image extensions but the image has " + std::to_string(count));
  }
  return hdus[std::size_t(e)];
}

RunSettings settingsForExtension(const RunSettings& settings, int e, int count) {
  RunSettings out = settings;
  // The images themselves by their HDU (a single image may sit in an extension: file.fits[1]).
  for (std::string& image : out.imagePaths) {
    const std::vector<std::string> hdus = listImageHdus(image);
    if (int(hdus.size()) != count) {
      throw IoError(image + ": has " + std::to_string(hdus.size()) +
                    " image extensions but the detection image has " + std::to_string(count));
    }
    image = hdus[std::size_t(e)];
  }
  if (!out.backgroundMapPath.empty()) {
    out.backgroundMapPath = extensionPath(out.backgroundMapPath, e, count, "BACKGROUND map");
  }
  if (!out.backgroundRmsMapPath.empty()) {
    out.backgroundRmsMapPath =
        extensionPath(out.backgroundRmsMapPath, e, count, "BACKGROUND_RMS map");
  }
  if (!out.weightImagePath.empty()) {
    out.weightImagePath = extensionPath(out.weightImagePath, e, count, "weight map");
  }
  if (out.dualImage() && !out.measurement.weightImagePath.empty()) {
    out.measurement.weightImagePath =
        extensionPath(out.measurement.weightImagePath, e, count, "measurement weight map");
  }
  return out;
}

std::string resolveFilterFile(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string resolved = userOrDataFile(path);
  if (resolved != path || fs::exists(path) || fs::path(path).has_parent_path()) return resolved;
  const fs::path sextractorShare = fs::path("/usr/share/source-extractor");
  if (fs::exists(sextractorShare / path)) return (sextractorShare / path).string();
  throw IoError(path + ": FILTER_NAME file not found (neither in the working directory, nor in " +
                dataDirectory() + ", nor in " + sextractorShare.string() + ")");
}

MeasureContext PreparedImage::context(const RunSettings& settings) const {
  return context(settings.magZeropoint, settings.pixelScaleArcsec);
}

MeasureContext PreparedImage::context(double magZeropoint, double pixelScaleArcsec) const {
  MeasureContext c;
  c.measurement = &hdu.pixels;
  c.detection = &detectionImage();
  c.saturatedPixels = saturatedPixels.empty() ? nullptr : &saturatedPixels;
  c.variance = variance.empty() ? nullptr : &variance;
  c.sigmaAdu = sigmaAdu;
  c.gain = gain;
  c.magZeropoint = magZeropoint;
  c.pixelScaleArcsec = pixelScaleArcsec;
  c.wcs = wcs ? &*wcs : nullptr;
  return c;
}

ImageF PreparedImage::backgroundImage() const {
  if (backgroundMap) return *backgroundMap;
  if (origin.background == "AUTO" && mesh) return mesh->levelImage();
  return ImageF(hdu.pixels.width(), hdu.pixels.height(), float(backgroundAdu));
}

ImageF PreparedImage::backgroundRmsImage() const {
  if (backgroundRmsMap) return *backgroundRmsMap;
  if (origin.background == "AUTO" && mesh) return mesh->rmsImage();
  return ImageF(hdu.pixels.width(), hdu.pixels.height(), float(sigmaAdu));
}

void PreparedImage::reloadVariance(const RunSettings& settings) {
  if (!varianceFiltered) return;
  variance = ImageF();  // freed before the map is read again
  ImageF weights = weightReader ? checkMapLike(weightReader(), "weights", hdu, "weight map")
                                : readMapLike(settings.weightImagePath, hdu, "weight map");
  weightsToVariance(weights, *mesh, settings);
  variance = std::move(weights);
  varianceFiltered = false;
}

namespace {

// Gain and saturation: the catalog's SEXGAIN is what SExtractor used; otherwise the header
// keyword named by GAIN_KEY / SATUR_KEY wins over the configuration, as in SExtractor. A header
// value that is not a finite number >= 0 is ignored with a warning (the configuration's value
// is used), since it cannot be a gain or a saturation level.
void readGainAndSaturation(PreparedImage& out, const std::string& imagePath,
                           const RunSettings& settings, const CatalogRunValues& fromCatalog) {
  if (fromCatalog.gain) {
    out.gain = *fromCatalog.gain;
  } else {
    out.gain = headerNonNegative(
                   out.hdu.header, settings.gainKey, imagePath,
                   "GAIN " + formatNumber(settings.gainElectronPerAdu) + " of the configuration",
                   out.warnings)
                   .value_or(settings.gainElectronPerAdu);
  }
  out.saturationAdu = headerNonNegative(out.hdu.header, settings.saturationKey, imagePath,
                                        "SATUR_LEVEL " + formatNumber(settings.saturationAdu) +
                                            " of the configuration",
                                        out.warnings)
                          .value_or(settings.saturationAdu);
}

// The weight map, read into the buffer that becomes the variance map (so that weights cost one
// image-sized buffer); no map for WEIGHT_TYPE NONE. From `maps` when it has the weights.
WeightMap openWeightMap(const RunSettings& settings, const ImageHdu& image, const ImageMaps& maps,
                        ImageF& buffer) {
  WeightMap weights;
  if (settings.weightType == WeightType::None) return weights;
  buffer = maps.weights ? checkMapLike(maps.weights(), "weights", image, "weight map")
                        : readMapLike(settings.weightImagePath, image, "weight map");
  weights.pixels = &buffer;
  weights.type = settings.weightType == WeightType::MapWeight ? WeightMapType::Weight
                 : settings.weightType == WeightType::MapRms  ? WeightMapType::Rms
                                                              : WeightMapType::Variance;
  weights.threshold = settings.weightThreshold;
  weights.rescale = settings.rescaleWeights;
  weights.name = maps.weights ? std::string("weights") : settings.weightImagePath;
  return weights;
}

// The background level, subtracted, and the noise sigma, in order of precedence. Level: a
// BACKGROUND check-image, the input catalog's SEXBKGND, then BACK_TYPE. Sigma: the input
// catalog's SEXBKDEV, a BACKGROUND_RMS check-image, then the background estimate itself (as
// SExtractor, the mesh RMS even for a MANUAL level). The mesh is estimated once, when first
// needed, and always with a weight map (RESCALE_WEIGHTS comes from its statistics).
void subtractBackground(PreparedImage& out, const std::string& imagePath,
                        const RunSettings& settings, const CatalogRunValues& fromCatalog,
                        const WeightMap& weights, const ImageMaps& maps, bool keepCheckMaps) {
  ImageF& pixels = out.hdu.pixels;
  std::optional<MeshBackground>& mesh = out.mesh;
  auto meshBackground = [&]() -> const MeshBackground& {
    if (!mesh) {
      MeshBackgroundSettings ms;
      ms.meshWidth = settings.backMeshWidthPix;
      ms.meshHeight = settings.backMeshHeightPix;
      ms.filterWidth = settings.backFilterWidth;
      ms.filterHeight = settings.backFilterHeight;
      ms.filterThresholdAdu = settings.backFilterThresholdAdu;
      ms.threadCount = settings.threads;
      mesh = weights.pixels ? MeshBackground::estimate(pixels, ms, weights, imagePath)
                            : MeshBackground::estimate(pixels, ms, imagePath);
    }
    return *mesh;
  };
  if (weights.pixels) meshBackground();

  std::optional<double> sigmaAdu = fromCatalog.sigmaAdu;
  if (sigmaAdu) out.origin.sigma = "CATALOG";
  if (!sigmaAdu && !settings.backgroundRmsMapPath.empty()) {
    ImageF rms = readMapLike(settings.backgroundRmsMapPath, out.hdu, "BACKGROUND_RMS map");
    sigmaAdu = finiteMedian(rms);
    out.origin.sigma = "CHECKIMAGE";
    if (keepCheckMaps) out.backgroundRmsMap = std::move(rms);
  }
  auto sigmaFromMesh = [&]() {
    if (!sigmaAdu) {
      sigmaAdu = meshBackground().globalSigmaAdu();
      out.origin.sigma = "MESH_MEDIAN";
    }
  };

  if (maps.background || !settings.backgroundMapPath.empty()) {
    ImageF map = maps.background
                     ? checkMapLike(maps.background(), "background", out.hdu, "BACKGROUND map")
                     : readMapLike(settings.backgroundMapPath, out.hdu, "BACKGROUND map");
    out.backgroundAdu = finiteMedian(map);
    out.origin.background = "CHECKIMAGE";
    sigmaFromMesh();
    subtractMap(pixels, map);
    if (keepCheckMaps) out.backgroundMap = std::move(map);
  } else if (fromCatalog.backgroundAdu) {
    out.backgroundAdu = *fromCatalog.backgroundAdu;
    out.origin.background = "CATALOG";
    sigmaFromMesh();
    subtractConstant(pixels, out.backgroundAdu);
  } else if (settings.backgroundType == BackgroundType::Manual) {
    out.backgroundAdu = settings.backgroundValueAdu;
    out.origin.background = "MANUAL";
    sigmaFromMesh();
    subtractConstant(pixels, out.backgroundAdu);
  } else if (settings.backgroundType == BackgroundType::Global) {
    const GlobalBackground global =
        estimateGlobalBackground(pixels, 3.0, 100, imagePath, settings.threads);
    out.backgroundAdu = global.levelAdu;
    out.origin.background = "GLOBAL";
    if (!sigmaAdu) {
      sigmaAdu = global.sigmaAdu;
      out.origin.sigma = "CLIPPED_RMS";
    }
    if (!global.warning.empty()) out.warnings.push_back(global.warning);
    subtractConstant(pixels, out.backgroundAdu);
  } else {
    const MeshBackground& m = meshBackground();
    out.backgroundAdu = m.globalLevelAdu();
    out.origin.background = "AUTO";
    sigmaFromMesh();
    // Row by row, so that no image-sized background map is needed; rows split between threads.
    parallelBlocks(pixels.height(), resolveThreads(settings.threads),
                   [&](std::int64_t y0, std::int64_t y1) {
                     for (std::int64_t y = y0; y < y1; ++y) {
                       m.subtractRow(y, pixels.data() + y * pixels.width());
                     }
                   });
  }
  if (mesh) {
    // The background stage's warnings already start with the file name.
    for (const std::string& w : mesh->warnings()) out.warnings.push_back(w);
  }
  out.sigmaAdu = *sigmaAdu;
}

// The variance map from the weights, and the filtered detection image (FILTER Y).
void varianceAndFilter(PreparedImage& out, const RunSettings& settings, const ImageMaps& maps,
                       ImageF& weightPixels, bool haveWeights, bool filterVariance) {
  std::optional<ConvKernel> kernel;
  if (settings.filter) {
    kernel = maps.filter ? *maps.filter
                         : sexcompat::readConvFile(resolveFilterFile(settings.filterPath));
  }
  if (haveWeights) {
    weightsToVariance(weightPixels, *out.mesh, settings);
    out.weightScale = out.mesh->weightScale();
    if (kernel && filterVariance) {
      // SExtractor thresholds the filtered image against the variance filtered by the same
      // kernel; its bad pixels carry a variance of 1e30 (not Inf, which 0 * Inf would turn
      // into NaN). The unfiltered map is dropped before the image is filtered, so that at most
      // three image-sized buffers exist; reloadVariance() brings it back for measurements.
      for (float& v : weightPixels.pixels()) v = std::min(v, 1e30f);
      out.variance = applyFilter(weightPixels, *kernel, settings.threads);
      out.varianceFiltered = true;
      weightPixels = ImageF();
    } else {
      out.variance = std::move(weightPixels);
    }
  }
  if (kernel) out.filtered = applyFilter(out.hdu.pixels, *kernel, settings.threads);
}

}  // namespace

namespace {

// prepareImage's steps on an image in memory (`out.hdu`).
void prepareLoaded(PreparedImage& out, const std::string& imagePath, const RunSettings& settings,
                   const CatalogRunValues& fromCatalog, const ImageMaps& maps, bool keepCheckMaps,
                   bool filterVariance) {
  ImageF& pixels = out.hdu.pixels;
  const bool anyFinite = std::any_of(pixels.pixels().begin(), pixels.pixels().end(),
                                     [](float v) { return std::isfinite(v); });
  if (!anyFinite) throw IoError(imagePath + ": image has no finite pixel (all NaN or Inf)");
  readGainAndSaturation(out, imagePath, settings, fromCatalog);
  // SATUR_LEVEL applies to raw values, so saturated pixels are found before the background goes.
  out.saturatedPixels = findSaturatedPixels(pixels, out.saturationAdu, settings.threads);
  ImageF weightPixels;
  const WeightMap weights = openWeightMap(settings, out.hdu, maps, weightPixels);
  subtractBackground(out, imagePath, settings, fromCatalog, weights, maps, keepCheckMaps);
  varianceAndFilter(out, settings, maps, weightPixels, weights.pixels != nullptr, filterVariance);
  out.wcs = Wcs::fromHeader(out.hdu.header, imagePath);
}

}  // namespace

PreparedImage prepareImage(const std::string& imagePath, const RunSettings& settings,
                           const CatalogRunValues& fromCatalog, bool keepCheckMaps,
                           bool filterVariance) {
  PreparedImage out;
  out.hdu = readImage(imagePath);
  prepareLoaded(out, imagePath, settings, fromCatalog, ImageMaps(), keepCheckMaps, filterVariance);
  return out;
}

PreparedImage prepareImage(ImageHdu image, const std::string& imageName,
                           const RunSettings& settings, const ImageMaps& maps,
                           const CatalogRunValues& given, bool filterVariance) {
  PreparedImage out;
  out.hdu = std::move(image);
  if (settings.weightType != WeightType::None) out.weightReader = maps.weights;
  prepareLoaded(out, imageName, settings, given, maps, false, filterVariance);
  return out;
}

namespace {

// True when every corner pixel of the image lands within `tolerancePix` of itself when taken to
// the sky by `from` and back by `to` (a different world frame fails: its numbers differ).
bool sameGrid(const Wcs& from, const Wcs& to, std::int64_t width, std::int64_t height,
              double tolerancePix) {
  const double corners[4][2] = {
      {1.0, 1.0}, {double(width), 1.0}, {1.0, double(height)}, {double(width), double(height)}};
  for (const auto& c : corners) {
    const std::array<double, 2> world = from.pixelToWorld(c[0], c[1]);
    const std::array<double, 2> back = to.worldToPixel(world[0], world[1]);
    if (!(std::hypot(back[0] - c[0], back[1] - c[1]) <= tolerancePix)) return false;
  }
  return true;
}

}  // namespace

std::string pixelGridDifference(std::int64_t widthA, std::int64_t heightA,
                                const std::optional<Wcs>& wcsA, std::int64_t widthB,
                                std::int64_t heightB, const std::optional<Wcs>& wcsB) {
  if (widthA != widthB || heightA != heightB) {
    return std::to_string(widthA) + "x" + std::to_string(heightA) + " and " +
           std::to_string(widthB) + "x" + std::to_string(heightB) + " pixels";
  }
  if (wcsA && wcsB && !sameGrid(*wcsA, *wcsB, widthA, heightA, 0.1)) {
    return "their WCS put a corner more than 0.1 pixel apart";
  }
  return "";
}

PreparedImage prepareDualImage(const std::string& detectionPath, const std::string& measurementPath,
                               const RunSettings& settings, bool keepCheckMaps,
                               bool filterVariance) {
  PreparedImage detection = prepareImage(detectionPath, settings, {}, false, filterVariance);
  PreparedImage out =
      prepareImage(measurementPath, measurementImageSettings(settings), {}, keepCheckMaps, false);
  const ImageF& d = detection.hdu.pixels;
  const ImageF& m = out.hdu.pixels;
  const std::string difference =
      pixelGridDifference(d.width(), d.height(), detection.wcs, m.width(), m.height(), out.wcs);
  if (!difference.empty()) {
    throw IoError(detectionPath + " and " + measurementPath +
                  ": the detection and measurement images must share one pixel grid (" +
                  difference + ")");
  }
  out.separateDetection = true;
  out.detectionSigmaAdu = detection.sigmaAdu;
  out.detectionWeightScale = detection.weightScale;
  out.detectionVariance = std::move(detection.variance);
  out.filtered =
      detection.filtered.empty() ? std::move(detection.hdu.pixels) : std::move(detection.filtered);
  std::vector<std::string> warnings = std::move(detection.warnings);
  warnings.insert(warnings.end(), out.warnings.begin(), out.warnings.end());
  out.warnings = std::move(warnings);
  return out;
}

PreparedImage prepareRunImage(const RunSettings& settings, int e, int count, bool keepCheckMaps,
                              bool filterVariance) {
  const RunSettings s = settingsForExtension(settings, e, count);
  if (s.dualImage()) {
    return prepareDualImage(s.detectionImagePath(), s.measurementImagePath(), s, keepCheckMaps,
                            filterVariance);
  }
  return prepareImage(s.imagePaths.front(), s, {}, keepCheckMaps, filterVariance);
}

std::vector<std::int64_t> findSaturatedPixels(const ImageF& raw, double levelAdu, int threads) {
  std::vector<std::int64_t> saturated;
  if (!(levelAdu > 0)) return saturated;
  // Blocks of pixels on every worker, each listing its own; joined in order.
  const int workers = std::max(1, resolveThreads(threads));
  std::vector<std::vector<std::int64_t>> found(static_cast<std::size_t>(workers));
  const float* data = raw.data();
  const std::int64_t n = raw.size();
  parallelBlocks(workers, workers, [&](std::int64_t w0, std::int64_t w1) {
    for (std::int64_t w = w0; w < w1; ++w) {
      const std::int64_t end = n * (w + 1) / workers;
      for (std::int64_t p = n * w / workers; p < end; ++p) {
        if (data[p] >= levelAdu) found[std::size_t(w)].push_back(p);
      }
    }
  });
  for (const std::vector<std::int64_t>& band : found) {
    saturated.insert(saturated.end(), band.begin(), band.end());
  }
  return saturated;
}

}  // namespace octarc
