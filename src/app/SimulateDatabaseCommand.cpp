// `octarc simulate database`: a source-galaxy database cut out of a deep image, the way the
// paper built its own (METHOD.md section 3: threshold at 4 sigma, clean, noise-free stamps).
//
//   image --> mesh background and noise sigma --> detection at one threshold (k sigma)
//         --> per object: skip border / small / saturated, cut the clean stamp (GalaxyCutout.h)
//         --> magnitude, position --> RealGalaxyCatalog table + stamp file (+ PSF file)

#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Progress.h"
#include "octarc/simulation/GalaxyCutout.h"
#include "octarc/simulation/RealGalaxyCatalogWriter.h"
#include "octarc/simulation/engine/SourceDatabaseBuilder.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

namespace {

namespace po = boost::program_options;

// The builder's settings, plus what only the command has.
struct DatabaseOptions : SourceDatabaseSettings {
  std::string outputPath;
  std::string configPath;
  bool quiet = false;
};

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

// Parses the arguments; nullopt after --help.
std::optional<DatabaseOptions> parseDatabaseOptions(const std::vector<std::string>& args) {
  DatabaseOptions o;
  double threshold = o.thresholdSigma;
  int minArea = 0, minSize = o.minSizePixels, margin = o.marginPixels;
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
      ("threshold", po::value(&threshold)->default_value(threshold, "4")->value_name("SIGMA"),
       "detection threshold in units of the background sigma")  //
      ("min-area", po::value(&minArea)->value_name("N"),
       "smallest object detected, pixels (DETECT_MINAREA; default 5)")  //
      ("min-size", po::value(&minSize)->default_value(minSize)->value_name("N"),
       "smallest footprint kept as a galaxy, pixels")  //
      ("margin", po::value(&margin)->default_value(margin)->value_name("N"),
       "zero pixels around the footprint in each stamp")  //
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
      ("max-galaxies", po::value(&maxGalaxies)->default_value(0)->value_name("N"),
       "keep only the N brightest galaxies (0: all)")  //
      ("psf-fwhm", po::value(&psfFwhm)->value_name("ARCSEC"),
       "also write a Gaussian PSF of this FWHM and name it in PSF_FILENAME")  //
      ("quiet,q", po::bool_switch(&o.quiet), "no progress bar and no summary");
  const std::optional<ParsedOptions> parsed = parseOptions(
      args,
      {"simulate database", [&] { std::cout << kUsage << kOptionsAsKeys << "\n"
                                            << visible; }, {}},
      visible, 1);
  if (!parsed) return std::nullopt;
  const po::variables_map& vm = parsed->values;
  if (!parsed->positional.empty()) o.imagePath = parsed->positional[0];
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

}  // namespace

int runBuildDatabase(const std::vector<std::string>& args) {
  using namespace simulation;
  const auto start = std::chrono::steady_clock::now();
  std::optional<DatabaseOptions> parsed = parseDatabaseOptions(args);
  if (!parsed) return 0;
  DatabaseOptions& o = *parsed;
  if (!o.configPath.empty()) {
    o.survey = readSurveySettings(o.configPath);
    if (!o.quiet) {
      for (const std::string& w : o.survey->warnings) {
        std::cerr << "octarc simulate database: " << w << "\n";
      }
    }
  }

  checkSourceDatabaseOutputs(o.outputPath, o);
  const SourceDatabaseBuild build =
      buildSourceDatabase(o, terminalProgress("cutting stamps", "objects", o.quiet));
  if (!o.quiet) {
    for (const std::string& w : build.warnings)
      std::cerr << "octarc simulate database: " << w << "\n";
  }
  const RealGalaxyCatalogPaths written =
      writeSourceDatabase(o.outputPath, build, o, octarcVersion());

  if (!o.quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fputs(sourceDatabaseSummary(build, o, written, seconds).c_str(), stdout);
  }
  return 0;
}

}  // namespace octarc
