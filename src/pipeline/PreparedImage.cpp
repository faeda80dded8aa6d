#include "octarc/pipeline/PreparedImage.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "octarc/background/GlobalBackground.h"
#include "octarc/background/MeshBackground.h"
#include "octarc/core/Error.h"
#include "octarc/detection/Filter.h"
#include "octarc/pipeline/RunSettings.h"
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

ImageF readMapLike(const std::string& path, const ImageHdu& image, const char* what) {
  ImageHdu map = readImage(path);
  if (map.pixels.width() != image.pixels.width() || map.pixels.height() != image.pixels.height()) {
    throw IoError(path + ": " + what + " is " + std::to_string(map.pixels.width()) + "x" +
                  std::to_string(map.pixels.height()) + " but the image is " +
                  std::to_string(image.pixels.width()) + "x" +
                  std::to_string(image.pixels.height()));
  }
  return std::move(map.pixels);
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

// A .conv file named without a directory that is not in the working directory is looked up,
// as a convenience, in octarc's params/ and then in Debian's source-extractor share directory.
std::string resolveFilterFile(const std::string& path) {
  namespace fs = std::filesystem;
  if (fs::exists(path) || fs::path(path).has_parent_path()) return path;
  for (const char* dir : {OCTARC_PARAMS_DIR, "/usr/share/source-extractor"}) {
    const fs::path candidate = fs::path(dir) / path;
    if (fs::exists(candidate)) return candidate.string();
  }
  return path;
}

}  // namespace

double thresholdToAdu(double value, bool relative, double sigmaAdu) {
  return relative ? value * sigmaAdu : value;
}

MeasureContext PreparedImage::context(const RunSettings& settings) const {
  MeasureContext c;
  c.measurement = &hdu.pixels;
  c.detection = &detectionImage();
  c.saturatedPixels = saturatedPixels.empty() ? nullptr : &saturatedPixels;
  c.sigmaAdu = sigmaAdu;
  c.gain = gain;
  c.magZeropoint = settings.magZeropoint;
  c.pixelScaleArcsec = settings.pixelScaleArcsec;
  c.wcs = wcs ? &*wcs : nullptr;
  return c;
}

PreparedImage prepareImage(const std::string& imagePath, const RunSettings& settings,
                           const CatalogRunValues& fromCatalog, bool keepCheckMaps) {
  PreparedImage out;
  out.hdu = readImage(imagePath);
  ImageF& pixels = out.hdu.pixels;
  const bool anyFinite = std::any_of(pixels.pixels().begin(), pixels.pixels().end(),
                                     [](float v) { return std::isfinite(v); });
  if (!anyFinite) throw IoError(imagePath + ": image has no finite pixel (all NaN or Inf)");

  // Gain and saturation: the catalog's SEXGAIN is what SExtractor used; otherwise the header
  // keyword named by GAIN_KEY / SATUR_KEY wins over the configuration, as in SExtractor.
  if (fromCatalog.gain) {
    out.gain = *fromCatalog.gain;
  } else {
    out.gain = out.hdu.header.number(settings.gainKey).value_or(settings.gainElectronPerAdu);
  }
  out.saturationAdu =
      out.hdu.header.number(settings.saturationKey).value_or(settings.saturationAdu);
  // SATUR_LEVEL applies to raw values, so saturated pixels are found before the background goes.
  if (out.saturationAdu > 0) {
    for (std::int64_t p = 0; p < pixels.size(); ++p) {
      if (pixels[p] >= out.saturationAdu) out.saturatedPixels.push_back(p);
    }
  }

  // Background level, in order of precedence: a BACKGROUND check-image, the input catalog's
  // SEXBKGND, then BACK_TYPE. The noise sigma: the input catalog's SEXBKDEV, a BACKGROUND_RMS
  // check-image, then the background estimate itself (as SExtractor, the mesh RMS even for a
  // MANUAL level).
  std::optional<MeshBackground> mesh;
  auto meshBackground = [&]() -> const MeshBackground& {
    if (!mesh) {
      MeshBackgroundSettings ms;
      ms.meshWidth = settings.backMeshWidthPix;
      ms.meshHeight = settings.backMeshHeightPix;
      ms.filterWidth = settings.backFilterWidth;
      ms.filterHeight = settings.backFilterHeight;
      ms.filterThresholdAdu = settings.backFilterThresholdAdu;
      ms.threadCount = settings.threads;
      mesh = MeshBackground::estimate(pixels, ms, imagePath);
    }
    return *mesh;
  };

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

  if (!settings.backgroundMapPath.empty()) {
    ImageF map = readMapLike(settings.backgroundMapPath, out.hdu, "BACKGROUND map");
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
    if (keepCheckMaps) {
      out.backgroundMap = m.levelImage();
      if (!out.backgroundRmsMap) out.backgroundRmsMap = m.rmsImage();
    }
    // Row by row, so that no image-sized background map is needed.
    for (std::int64_t y = 0; y < pixels.height(); ++y) {
      m.subtractRow(y, pixels.data() + y * pixels.width());
    }
  }
  if (mesh) {
    for (const std::string& w : mesh->warnings()) out.warnings.push_back(imagePath + ": " + w);
  }
  out.sigmaAdu = *sigmaAdu;

  if (settings.filter) {
    const ConvKernel kernel = sexcompat::readConvFile(resolveFilterFile(settings.filterPath));
    out.filtered = applyFilter(pixels, kernel, settings.threads);
  }
  out.wcs = Wcs::fromHeader(out.hdu.header, imagePath);
  return out;
}

}  // namespace octarc
