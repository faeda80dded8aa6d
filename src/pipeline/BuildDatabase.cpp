// `octarc simulate database`: a source-galaxy database cut out of a deep image, the way the
// paper built its own (METHOD.md section 3: threshold at 4 sigma, clean, noise-free stamps).
//
//   image --> mesh background and noise sigma --> detection at one threshold (k sigma)
//         --> per object: skip border / small / saturated, cut the clean stamp (GalaxyCutout.h)
//         --> magnitude, position --> RealGalaxyCatalog table + stamp file (+ PSF file)

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

#include "octarc/background/MeshBackground.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Progress.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/pipeline/CommandLine.h"
#include "octarc/pipeline/Pipeline.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/Keys.h"
#include "octarc/simulation/GalaxyCutout.h"
#include "octarc/simulation/Psf.h"
#include "octarc/simulation/RealGalaxyCatalogWriter.h"

namespace octarc {

namespace {

namespace po = boost::program_options;

const char* const kUsage =
    "Usage: octarc simulate database IMAGE -o CATALOG.fits [options]\n"
    "\n"
    "Cuts clean, noise-free galaxy stamps out of a deep image and writes them as a source-galaxy\n"
    "database in GalSim's RealGalaxyCatalog format (CATALOG.fits, CATALOG_images.fits and,\n"
    "with --psf-fwhm, CATALOG_psf.fits), ready for `octarc simulate lenses --database`.\n"
    "\n"
    "The background is SExtractor's mesh background; objects are the 8-connected pixels above\n"
    "--threshold times the background sigma (no filter, no deblending). A stamp keeps the\n"
    "background-subtracted pixels of its object's footprint and is zero everywhere else, so the\n"
    "sky noise below the threshold and every other object are removed. Objects touching the\n"
    "image border, smaller than --min-size pixels or with a saturated pixel are skipped.\n"
    "\n";

// Survey-independent defaults of the builder.
constexpr double kDefaultThresholdSigma = 4.0;  // the paper's 4 sigma
constexpr int kDefaultMinSizePixels = 25;       // smaller objects are barely resolved
constexpr int kDefaultMarginPixels = 4;

struct DatabaseOptions {
  std::string imagePath;
  std::string outputPath;
  std::string configPath;
  double thresholdSigma = kDefaultThresholdSigma;
  std::optional<int> minAreaPixels;
  int minSizePixels = kDefaultMinSizePixels;
  int marginPixels = kDefaultMarginPixels;
  std::optional<double> pixelScaleArcsec;
  std::optional<std::string> band;
  std::optional<double> zeroPointMag;
  std::optional<double> saturationAdu;
  std::optional<double> psfFwhmArcsec;
  std::int64_t maxGalaxies = 0;  // 0: all
  bool quiet = false;
};

// A number as the user would write it ("4", "0.05", "-1e+30"), for messages.
// A value with where it came from, for the summary.
template <typename T>
struct Sourced {
  T value{};
  std::string origin;
};

// Parses the arguments; nullopt after --help.
std::optional<DatabaseOptions> parseOptions(const std::vector<std::string>& args) {
  DatabaseOptions o;
  double threshold = kDefaultThresholdSigma;
  int minArea = 0, minSize = kDefaultMinSizePixels, margin = kDefaultMarginPixels;
  double pixelScale = 0, zeroPoint = 0, saturation = 0, psfFwhm = 0;
  long long maxGalaxies = 0;
  std::string band;
  po::options_description visible("Options");
  visible.add_options()        //
      ("help,h", "this help")  //
      ("output,o", po::value(&o.outputPath)->value_name("CATALOG.fits"),
       "the catalog to write (required)")  //
      ("config,c", po::value(&o.configPath)->value_name("FILE.sex"),
       "octarc/SExtractor configuration: BACK_SIZE, BACK_FILTERSIZE, BACK_FILTTHRESH, "
       "DETECT_MINAREA, SATUR_LEVEL, MAG_ZEROPOINT and PIXEL_SCALE are taken from it when set")  //
      ("threshold", po::value(&threshold)->value_name("SIGMA"),
       "detection threshold in units of the background sigma (default 4)")  //
      ("min-area", po::value(&minArea)->value_name("N"),
       "smallest object detected, pixels (DETECT_MINAREA; default 5)")  //
      ("min-size", po::value(&minSize)->value_name("N"),
       "smallest footprint kept as a galaxy, pixels (default 25)")  //
      ("margin", po::value(&margin)->value_name("N"),
       "zero pixels around the footprint in each stamp (default 4)")  //
      ("pixel-scale", po::value(&pixelScale)->value_name("ARCSEC"),
       "pixel size; default: PIXEL_SCALE of --config, the WCS, or the PIXSCALE/PIXSCAL1/SECPIX "
       "header keyword")  //
      ("band", po::value(&band)->value_name("NAME"),
       "BAND of the catalog (default: the FILTER header keyword, else UNKNOWN)")  //
      ("zeropoint", po::value(&zeroPoint)->value_name("MAG"),
       "magnitude zero point: MAG = ZP - 2.5 log10(flux in ADU) (default: MAG_ZEROPOINT of "
       "--config, the MAGZERO/MAGZPT/ZEROPNT header keyword, else 0)")  //
      ("saturation", po::value(&saturation)->value_name("ADU"),
       "objects with a raw pixel at or above this are skipped (default: SATUR_LEVEL of "
       "--config, the SATURATE header keyword, else none)")  //
      ("max-galaxies", po::value(&maxGalaxies)->value_name("N"),
       "keep only the N brightest galaxies (default: all)")  //
      ("psf-fwhm", po::value(&psfFwhm)->value_name("ARCSEC"),
       "also write a Gaussian PSF of this FWHM and name it in PSF_FILENAME")  //
      ("quiet,q", po::bool_switch(&o.quiet), "no progress bar and no summary");
  po::options_description hidden;
  hidden.add_options()("image", po::value(&o.imagePath));
  po::options_description all;
  all.add(visible).add(hidden);
  po::positional_options_description positional;
  positional.add("image", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string(e.what()) + " (see octarc simulate database -h)");
  }
  if (vm.count("help")) {
    std::cout << kUsage << visible;
    return std::nullopt;
  }
  if (o.imagePath.empty()) throw ConfigError("IMAGE: give the deep image to cut galaxies from");
  if (o.outputPath.empty()) throw ConfigError("-o/--output: give the catalog file to write");
  if (!(threshold > 0) || !std::isfinite(threshold))
    throw ConfigError("--threshold must be a positive number of sigmas, got " +
                      formatNumber(threshold));
  if (vm.count("min-area")) {
    if (minArea < 1)
      throw ConfigError("--min-area must be at least 1 pixel, got " + std::to_string(minArea));
    o.minAreaPixels = minArea;
  }
  if (minSize < 1)
    throw ConfigError("--min-size must be at least 1 pixel, got " + std::to_string(minSize));
  if (margin < 0) throw ConfigError("--margin must not be negative, got " + std::to_string(margin));
  if (maxGalaxies < 0)
    throw ConfigError("--max-galaxies must not be negative, got " + std::to_string(maxGalaxies));
  if (vm.count("pixel-scale")) {
    if (!(pixelScale > 0) || !std::isfinite(pixelScale))
      throw ConfigError("--pixel-scale must be positive (arcsec), got " + formatNumber(pixelScale));
    o.pixelScaleArcsec = pixelScale;
  }
  if (vm.count("psf-fwhm")) {
    if (!(psfFwhm > 0) || !std::isfinite(psfFwhm))
      throw ConfigError("--psf-fwhm must be positive (arcsec), got " + formatNumber(psfFwhm));
    o.psfFwhmArcsec = psfFwhm;
  }
  if (vm.count("zeropoint")) {
    if (!std::isfinite(zeroPoint)) throw ConfigError("--zeropoint must be a finite number");
    o.zeroPointMag = zeroPoint;
  }
  if (vm.count("saturation")) o.saturationAdu = saturation;
  if (vm.count("band")) {
    if (band.empty()) throw ConfigError("--band must not be empty");
    o.band = band;
  }
  o.thresholdSigma = threshold;
  o.minSizePixels = minSize;
  o.marginPixels = margin;
  o.maxGalaxies = maxGalaxies;
  return o;
}

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

std::optional<double> headerNumber(const FitsHeader& header,
                                   std::initializer_list<const char*> keys, std::string* which) {
  for (const char* key : keys) {
    if (auto v = header.number(key)) {
      if (which) *which = key;
      return v;
    }
  }
  return std::nullopt;
}

Sourced<double> resolvePixelScale(const DatabaseOptions& o, const sexcompat::Config* config,
                                  const ImageHdu& image, const std::optional<Wcs>& wcs) {
  if (o.pixelScaleArcsec) return {*o.pixelScaleArcsec, "--pixel-scale"};
  if (config && config->isExplicit("PIXEL_SCALE") && config->getDouble("PIXEL_SCALE") > 0)
    return {config->getDouble("PIXEL_SCALE"), "PIXEL_SCALE of " + o.configPath};
  if (wcs) {
    const double xc = 0.5 * double(image.pixels.width() + 1);
    const double yc = 0.5 * double(image.pixels.height() + 1);
    if (auto scale = wcsPixelScaleArcsec(*wcs, xc, yc)) return {*scale, "WCS"};
  }
  std::string key;
  if (auto v = headerNumber(image.header, {"PIXSCALE", "PIXSCAL1", "SECPIX"}, &key)) {
    if (*v > 0 && std::isfinite(*v)) return {*v, "header " + key};
  }
  throw ConfigError("--pixel-scale: " + o.imagePath +
                    " has no WCS and no PIXSCALE/PIXSCAL1/SECPIX keyword; give the pixel size "
                    "in arcsec");
}

}  // namespace

int runBuildDatabase(const std::vector<std::string>& args) {
  using namespace simulation;
  const auto start = std::chrono::steady_clock::now();
  const std::optional<DatabaseOptions> parsed = parseOptions(args);
  if (!parsed) return 0;
  const DatabaseOptions& o = *parsed;

  std::optional<sexcompat::Config> config;
  if (!o.configPath.empty()) {
    std::vector<std::string> warnings;
    config = sexcompat::Config::load(sexcompat::octarcMeasureKeys(), o.configPath, {}, &warnings);
    if (!o.quiet) {
      for (const std::string& w : warnings) std::cerr << "octarc simulate database: " << w << "\n";
    }
  }
  const sexcompat::Config* cfg = config ? &*config : nullptr;
  auto explicitKey = [&](const char* key) { return cfg && cfg->isExplicit(key); };

  // The output files must not overwrite the image they are cut from.
  const RealGalaxyCatalogPaths outPaths =
      realGalaxyCatalogPaths(o.outputPath, o.psfFwhmArcsec.has_value());
  std::error_code ec;
  for (const std::string& out : {outPaths.catalog, outPaths.galaxyImages, outPaths.psfImage}) {
    if (!out.empty() && std::filesystem::equivalent(out, o.imagePath, ec))
      throw ConfigError("-o/--output: " + out + " would overwrite the input image");
  }
  const std::filesystem::path outDir = std::filesystem::path(o.outputPath).parent_path();
  if (!outDir.empty() && !std::filesystem::is_directory(outDir))
    throw ConfigError("-o/--output: directory " + outDir.string() + " does not exist");

  ImageHdu image = readImage(o.imagePath);
  ImageF& pixels = image.pixels;
  const std::int64_t width = pixels.width();
  const std::int64_t height = pixels.height();
  const std::optional<Wcs> wcs = Wcs::fromHeader(image.header, o.imagePath);
  const Sourced<double> pixelScale = resolvePixelScale(o, cfg, image, wcs);

  Sourced<double> zeroPoint{0.0, "default"};
  std::string key;
  if (o.zeroPointMag) {
    zeroPoint = {*o.zeroPointMag, "--zeropoint"};
  } else if (explicitKey("MAG_ZEROPOINT")) {
    zeroPoint = {cfg->getDouble("MAG_ZEROPOINT"), "MAG_ZEROPOINT"};
  } else if (auto v = headerNumber(image.header, {"MAGZERO", "MAGZPT", "ZEROPNT"}, &key)) {
    zeroPoint = {*v, "header " + key};
  }
  std::optional<double> saturationAdu = o.saturationAdu;
  if (!saturationAdu && explicitKey("SATUR_LEVEL")) saturationAdu = cfg->getDouble("SATUR_LEVEL");
  if (!saturationAdu) {
    std::vector<std::string> warnings;
    saturationAdu = headerNonNegative(image.header, "SATURATE", o.imagePath,
                                      "no saturation level (no pixel flagged saturated)", warnings);
    if (!o.quiet) {
      for (const std::string& w : warnings) std::cerr << "octarc simulate database: " << w << "\n";
    }
  }
  std::string band = "UNKNOWN";
  if (o.band) {
    band = *o.band;
  } else if (auto v = image.header.value("FILTER")) {
    if (!v->empty()) band = *v;
  }

  MeshBackgroundSettings mesh;
  if (explicitKey("BACK_SIZE")) {
    mesh.meshWidth = cfg->getInt("BACK_SIZE", 0);
    mesh.meshHeight = cfg->count("BACK_SIZE") > 1 ? cfg->getInt("BACK_SIZE", 1) : mesh.meshWidth;
  }
  if (explicitKey("BACK_FILTERSIZE")) {
    mesh.filterWidth = cfg->getInt("BACK_FILTERSIZE", 0);
    mesh.filterHeight =
        cfg->count("BACK_FILTERSIZE") > 1 ? cfg->getInt("BACK_FILTERSIZE", 1) : mesh.filterWidth;
  }
  if (explicitKey("BACK_FILTTHRESH")) mesh.filterThresholdAdu = cfg->getDouble("BACK_FILTTHRESH");
  const MeshBackground background = MeshBackground::estimate(pixels, mesh, o.imagePath);
  const double sigmaAdu = background.globalSigmaAdu();

  // Saturation is judged on the raw pixels, before the background is subtracted.
  const std::vector<std::int64_t> saturated =
      saturationAdu ? findSaturatedPixels(pixels, *saturationAdu, 0) : std::vector<std::int64_t>();
  for (std::int64_t y = 0; y < height; ++y) background.subtractRow(y, &pixels(0, y));

  DetectionRequest detect;
  detect.levels = levelsAtThresholds({o.thresholdSigma * sigmaAdu}, sigmaAdu);
  detect.minAreaPix = o.minAreaPixels                 ? *o.minAreaPixels
                      : explicitKey("DETECT_MINAREA") ? cfg->getInt("DETECT_MINAREA")
                                                      : 5;
  detect.threads = 0;
  std::vector<Segment> objects = detectSegments(pixels, detect);

  CutoutSettings cut;
  cut.minAreaPixels = o.minSizePixels;
  cut.marginPixels = o.marginPixels;
  std::map<CutoutVerdict, std::int64_t> verdicts;
  std::vector<RealGalaxyRecord> records;
  {
    const ProgressFn progress = terminalProgress("cutting stamps", "objects", o.quiet);
    for (std::size_t i = 0; i < objects.size(); ++i) {
      GalaxyCutout c = cutGalaxy(pixels, objects[i], saturated, cut);
      ++verdicts[c.verdict];
      if (c.verdict == CutoutVerdict::Kept) {
        RealGalaxyRecord r;
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
      why << ", " << count << " " << cutoutVerdictName(verdict);
    }
    throw ConfigError(o.imagePath + ": no galaxy to keep (" + std::to_string(objects.size()) +
                      " objects above " + formatNumber(o.thresholdSigma) + " sigma" + why.str() +
                      ")");
  }
  if (o.maxGalaxies > 0 && std::int64_t(records.size()) > o.maxGalaxies) {
    // The brightest (smallest MAG; IDENT breaks ties), then back in IDENT order.
    std::stable_sort(
        records.begin(), records.end(),
        [](const RealGalaxyRecord& a, const RealGalaxyRecord& b) { return a.mag < b.mag; });
    records.resize(std::size_t(o.maxGalaxies));
    std::sort(
        records.begin(), records.end(),
        [](const RealGalaxyRecord& a, const RealGalaxyRecord& b) { return a.ident < b.ident; });
  }

  RealGalaxyCatalogInfo info;
  info.band = band;
  info.pixelScaleArcsec = pixelScale.value;
  if (o.psfFwhmArcsec) info.psf = gaussianPsfImage(*o.psfFwhmArcsec, pixelScale.value);
  char card[81];
  std::snprintf(card, sizeof card,
                "HISTORY   octarc %s simulate database: %.4g sigma, sigma %.6g ADU",
                octarcVersion(), o.thresholdSigma, sigmaAdu);
  info.extraCards.push_back(card);
  std::snprintf(card, sizeof card, "HISTORY   source image %.56s",
                std::filesystem::path(o.imagePath).filename().string().c_str());
  info.extraCards.push_back(card);
  const RealGalaxyCatalogPaths written = writeRealGalaxyCatalog(o.outputPath, records, info);

  if (!o.quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ostringstream skipped;
    for (const auto& [verdict, count] : verdicts) {
      if (verdict != CutoutVerdict::Kept)
        skipped << "; " << count << " " << cutoutVerdictName(verdict);
    }
    std::printf(
        "%zu galaxies from %zu objects above %.3g sigma (%.6g ADU; background sigma %.6g "
        "ADU) in %lldx%lld pixels of %.4g\" (%s)%s\n",
        records.size(), objects.size(), o.thresholdSigma, o.thresholdSigma * sigmaAdu, sigmaAdu,
        (long long)width, (long long)height, pixelScale.value, pixelScale.origin.c_str(),
        skipped.str().c_str());
    std::printf("MAG zero point %.4f (%s); wrote %s, %s%s%s in %.1f s\n", zeroPoint.value,
                zeroPoint.origin.c_str(), written.catalog.c_str(), written.galaxyImages.c_str(),
                written.psfImage.empty() ? "" : ", ", written.psfImage.c_str(), seconds);
  }
  return 0;
}

}  // namespace octarc
