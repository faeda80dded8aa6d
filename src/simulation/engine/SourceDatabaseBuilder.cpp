#include "octarc/simulation/engine/SourceDatabaseBuilder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "octarc/background/MeshBackground.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/simulation/Psf.h"

namespace octarc {

namespace sim = simulation;

namespace {

// Pixel size (arcsec) from the WCS at the image centre: the square root of the sky area of one
// pixel, from the offsets to the neighbouring pixels in x and y.
std::optional<double> wcsPixelScaleArcsec(const Wcs& wcs, double xFits, double yFits) {
  const auto p0 = wcs.pixelToWorld(xFits, yFits);
  const auto px = wcs.pixelToWorld(xFits + 1.0, yFits);
  const auto py = wcs.pixelToWorld(xFits, yFits + 1.0);
  const double cosDec = std::cos(p0[1] * std::numbers::pi / 180.0);
  auto offset = [&](const std::array<double, 2>& p) {
    double dLng = p[0] - p0[0];
    dLng -= 360.0 * std::round(dLng / 360.0);  // across longitude 0
    return std::array<double, 2>{dLng * cosDec, p[1] - p0[1]};
  };
  const auto ex = offset(px);
  const auto ey = offset(py);
  const double areaDeg2 = std::abs(ex[0] * ey[1] - ex[1] * ey[0]);
  const double scale = std::sqrt(areaDeg2) * 3600.0;
  if (!std::isfinite(scale) || !(scale > 0)) return std::nullopt;
  return scale;
}

// The first of `keys` the header has, as a number in the range `accepted` says (IoError naming
// the image and the card otherwise: a card written by hand, not a missing one); nullopt when the
// header has none of them.
std::optional<double> headerNumber(const FitsHeader& header, const std::string& imagePath,
                                   std::initializer_list<const char*> keys, std::string* which,
                                   bool accepted(double), const char* expected) {
  for (const char* key : keys) {
    if (!header.has(key)) continue;
    const std::optional<double> v = header.number(key);
    if (!v || !accepted(*v)) {
      throw IoError(imagePath + ": " + key + " = " + header.value(key).value_or("") + " is not " +
                    expected);
    }
    if (which) *which = key;
    return v;
  }
  return std::nullopt;
}

bool finitePositive(double v) {
  return std::isfinite(v) && v > 0.0;
}
bool finiteNumber(double v) {
  return std::isfinite(v);
}

Sourced<double> resolvePixelScale(const SourceDatabaseSettings& o, const ImageHdu& image,
                                  const std::optional<Wcs>& wcs) {
  if (o.pixelScaleArcsec) return {*o.pixelScaleArcsec, "--pixel-scale"};
  if (o.survey && o.survey->pixelScaleArcsec)
    return {*o.survey->pixelScaleArcsec, "PIXEL_SCALE of " + o.survey->configPath};
  if (wcs) {
    const double xc = 0.5 * double(image.pixels.width() + 1);
    const double yc = 0.5 * double(image.pixels.height() + 1);
    if (auto scale = wcsPixelScaleArcsec(*wcs, xc, yc)) return {*scale, "WCS"};
  }
  std::string key;
  if (auto v = headerNumber(image.header, o.imagePath, {"PIXSCALE", "PIXSCAL1", "SECPIX"}, &key,
                            finitePositive, "a finite number > 0 (arcsec)")) {
    return {*v, "header " + key};
  }
  throw ConfigError("--pixel-scale: " + o.imagePath +
                    " has no WCS and no PIXSCALE/PIXSCAL1/SECPIX keyword; give the pixel size "
                    "in arcsec");
}

}  // namespace

SourceDatabaseBuild buildSourceDatabase(const SourceDatabaseSettings& o,
                                        const ProgressFn& progress) {
  SourceDatabaseBuild out;
  ImageHdu image = readImage(o.imagePath);
  ImageF& pixels = image.pixels;
  const std::int64_t width = pixels.width();
  const std::int64_t height = pixels.height();
  const std::optional<Wcs> wcs = Wcs::fromHeader(image.header, o.imagePath);
  out.pixelScale = resolvePixelScale(o, image, wcs);

  Sourced<double>& zeroPoint = out.zeroPoint;
  zeroPoint = {0.0, "default"};
  std::string key;
  if (o.zeroPointMag) {
    zeroPoint = {*o.zeroPointMag, "--zeropoint"};
  } else if (o.survey && o.survey->magZeropoint) {
    zeroPoint = {*o.survey->magZeropoint, "MAG_ZEROPOINT"};
  } else if (auto v = headerNumber(image.header, o.imagePath, {"MAGZERO", "MAGZPT", "ZEROPNT"},
                                   &key, finiteNumber, "a finite number (mag)")) {
    zeroPoint = {*v, "header " + key};
  }
  std::optional<double> saturationAdu = o.saturationAdu;
  if (!saturationAdu && o.survey) saturationAdu = o.survey->saturationAdu;
  if (!saturationAdu) {
    saturationAdu =
        headerNonNegative(image.header, "SATURATE", o.imagePath,
                          "no saturation level (no pixel flagged saturated)", out.warnings);
  }
  out.band = "UNKNOWN";
  if (o.band) {
    out.band = *o.band;
  } else if (auto v = image.header.value("FILTER")) {
    if (!v->empty()) out.band = *v;
  }

  MeshBackgroundSettings mesh;
  if (o.survey) {
    mesh.meshWidth = o.survey->backMeshWidthPix.value_or(mesh.meshWidth);
    mesh.meshHeight = o.survey->backMeshHeightPix.value_or(mesh.meshHeight);
    mesh.filterWidth = o.survey->backFilterWidth.value_or(mesh.filterWidth);
    mesh.filterHeight = o.survey->backFilterHeight.value_or(mesh.filterHeight);
    mesh.filterThresholdAdu = o.survey->backFilterThresholdAdu.value_or(mesh.filterThresholdAdu);
  }
  const MeshBackground background = MeshBackground::estimate(pixels, mesh, o.imagePath);
  const double sigmaAdu = background.globalSigmaAdu();
  out.sigmaAdu = sigmaAdu;
  out.widthPix = width;
  out.heightPix = height;

  // Saturation is judged on the raw pixels, before the background is subtracted.
  const std::vector<std::int64_t> saturated =
      saturationAdu ? findSaturatedPixels(pixels, *saturationAdu, 0) : std::vector<std::int64_t>();
  for (std::int64_t y = 0; y < height; ++y) background.subtractRow(y, &pixels(0, y));

  DetectionRequest detect;
  detect.levels = levelsAtThresholds({o.thresholdSigma * sigmaAdu}, sigmaAdu);
  detect.minAreaPix = o.minAreaPixels                    ? *o.minAreaPixels
                      : o.survey && o.survey->minAreaPix ? *o.survey->minAreaPix
                                                         : 5;
  detect.threads = 0;
  std::vector<Segment> objects = detectSegments(pixels, detect);
  out.objectCount = std::int64_t(objects.size());

  sim::CutoutSettings cut;
  cut.minAreaPixels = o.minSizePixels;
  cut.marginPixels = o.marginPixels;
  std::map<sim::CutoutVerdict, std::int64_t>& verdicts = out.verdicts;
  std::vector<sim::RealGalaxyRecord>& records = out.records;
  {
    for (std::size_t i = 0; i < objects.size(); ++i) {
      sim::GalaxyCutout c = cutGalaxy(pixels, objects[i], saturated, cut);
      ++verdicts[c.verdict];
      if (c.verdict == sim::CutoutVerdict::Kept) {
        sim::RealGalaxyRecord r;
        r.ident = objects[i].number;
        r.xImage = c.xCentroidPix + 1.0;  // FITS pixel coordinates
        r.yImage = c.yCentroidPix + 1.0;
        if (wcs) {
          const auto radec = wcs->pixelToJ2000(r.xImage, r.yImage);
          r.raDeg = radec[0];
          r.decDeg = radec[1];
        }
        r.mag = zeroPoint.value - 2.5 * std::log10(c.fluxAdu);
        // Inside the footprint the pixels keep the sky noise; outside they are exactly zero.
        r.noiseVariance = sigmaAdu * sigmaAdu;
        r.isoAreaPixels = c.areaPixels;
        r.stamp = std::move(c.stamp);
        records.push_back(std::move(r));
      }
      std::vector<std::int64_t>().swap(objects[i].pixels);
      if (progress) progress(std::int64_t(i + 1), std::int64_t(objects.size()));
    }
  }
  if (records.empty()) {
    std::ostringstream why;
    for (const auto& [verdict, count] : verdicts) {
      why << ", " << count << " " << sim::cutoutVerdictName(verdict);
    }
    throw ConfigError(o.imagePath + ": no galaxy to keep (" + std::to_string(objects.size()) +
                      " objects above " + formatNumber(o.thresholdSigma) + " sigma" + why.str() +
                      ")");
  }
  if (o.maxGalaxies > 0 && std::int64_t(records.size()) > o.maxGalaxies) {
    // The brightest (smallest MAG; IDENT breaks ties), then back in IDENT order.
    std::stable_sort(records.begin(), records.end(),
                     [](const sim::RealGalaxyRecord& a, const sim::RealGalaxyRecord& b) {
                       return a.mag < b.mag;
                     });
    records.resize(std::size_t(o.maxGalaxies));
    std::sort(records.begin(), records.end(),
              [](const sim::RealGalaxyRecord& a, const sim::RealGalaxyRecord& b) {
                return a.ident < b.ident;
              });
  }

  return out;
}

sim::RealGalaxyCatalogPaths writeSourceDatabase(const std::string& outputPath,
                                                const SourceDatabaseBuild& build,
                                                const SourceDatabaseSettings& o,
                                                const char* version) {
  sim::RealGalaxyCatalogInfo info;
  info.band = build.band;
  info.pixelScaleArcsec = build.pixelScale.value;
  // The PSF of an observed image, as a PSF image of the data would hold it: pixel-integrated.
  if (o.psfFwhmArcsec) {
    info.psf = sim::gaussianPsfImage(*o.psfFwhmArcsec, build.pixelScale.value,
                                     sim::PsfSampling::PixelIntegrated);
  }
  char card[81];
  std::snprintf(card, sizeof card,
                "HISTORY   octarc %s simulate database: %.4g sigma, sigma %.6g ADU", version,
                o.thresholdSigma, build.sigmaAdu);
  info.extraCards.push_back(card);
  std::snprintf(card, sizeof card, "HISTORY   source image %.56s",
                std::filesystem::path(o.imagePath).filename().string().c_str());
  info.extraCards.push_back(card);
  return writeRealGalaxyCatalog(outputPath, build.records, info);
}

void checkSourceDatabaseOutputs(const std::string& outputPath,
                                const SourceDatabaseSettings& settings) {
  const simulation::RealGalaxyCatalogPaths outPaths =
      simulation::realGalaxyCatalogPaths(outputPath, settings.psfFwhmArcsec.has_value());
  std::error_code ec;
  for (const std::string& out : {outPaths.catalog, outPaths.galaxyImages, outPaths.psfImage}) {
    if (!out.empty() && std::filesystem::equivalent(out, settings.imagePath, ec))
      throw ConfigError("-o/--output: " + out + " would overwrite the input image");
  }
  const std::filesystem::path outDir = std::filesystem::path(outputPath).parent_path();
  if (!outDir.empty() && !std::filesystem::is_directory(outDir))
    throw ConfigError("-o/--output: directory " + outDir.string() + " does not exist");
}

std::string sourceDatabaseSummary(const SourceDatabaseBuild& build,
                                  const SourceDatabaseSettings& settings,
                                  const simulation::RealGalaxyCatalogPaths& written,
                                  double seconds) {
  std::ostringstream skipped;
  for (const auto& [verdict, count] : build.verdicts) {
    if (verdict != simulation::CutoutVerdict::Kept)
      skipped << "; " << count << " " << simulation::cutoutVerdictName(verdict);
  }
  const double threshold = settings.thresholdSigma;
  char objects[1024], files[2048];
  std::snprintf(objects, sizeof objects,
                "%zu galaxies from %lld objects above %.3g sigma (%.6g ADU; background sigma "
                "%.6g ADU) in %lldx%lld pixels of %.4g\" (%s)%s\n",
                build.records.size(), (long long)build.objectCount, threshold,
                threshold * build.sigmaAdu, build.sigmaAdu, (long long)build.widthPix,
                (long long)build.heightPix, build.pixelScale.value, build.pixelScale.origin.c_str(),
                skipped.str().c_str());
  std::snprintf(files, sizeof files, "MAG zero point %.4f (%s); wrote %s, %s%s%s in %.1f s\n",
                build.zeroPoint.value, build.zeroPoint.origin.c_str(), written.catalog.c_str(),
                written.galaxyImages.c_str(), written.psfImage.empty() ? "" : ", ",
                written.psfImage.c_str(), seconds);
  return std::string(objects) + files;
}

}  // namespace octarc
