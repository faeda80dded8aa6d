// `octarc simulate field`: a survey-like image with injected lenses, its weight map and a truth
// list.
//
//   draws (one seeded stream) --> galaxy and lens stamps (threads, one stream each) --> sum
//   --> Gaussian PSF --> star stamps --> Poisson sky noise (per row band) --> saturation
//   --> FIELD.fits + FIELD.weight.fits + FIELD.truth.txt

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/pipeline/FieldSimulation.h"
#include "octarc/pipeline/LensSimulation.h"
#include "octarc/pipeline/Pipeline.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/Keys.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Noise.h"
#include "octarc/simulation/Psf.h"
#include "octarc/simulation/Seeds.h"

namespace octarc {

namespace po = boost::program_options;
using namespace octarc::simulation;

namespace {

// Independent random streams of one run: each gets its own seeds per object index.
enum Stream : std::uint64_t {
  kStreamLensPositions = 1,
  kStreamLenses = 2,
  kStreamPopulation = 3,
  kStreamGalaxies = 4,
  kStreamNoise = 5,
  kStreamGapNoise = 6,
  kStreamSources = 7,
};

std::mt19937_64 streamRng(std::uint64_t seed, Stream stream, std::uint64_t index) {
  return systemRng(systemSeed(seed, stream), index);
}

// Synthetic source galaxies drawn from for the lensed sources (as `octarc simulate lenses`).
constexpr int kSyntheticSources = 60;
// Draws per lens system at most, to reach the minimum Einstein radius.
constexpr int kMaxLensRedraws = 100000;
// Objects rendered per batch: stamps of one batch are kept, then summed in order.
constexpr std::size_t kRenderBatch = 4096;
// Rows per noise band (each band has its own stream, so threads do not change the result).
constexpr std::int64_t kNoiseBandRows = 64;

// Lens centres: uniform, at least `margin` pixels inside the edges, `separation` apart and off
// the chip gap.
std::vector<Vec2> drawLensPositions(const FieldSimulationSettings& s, int gapX0, int gapX1) {
  const double margin = std::max(48.0, 0.06 * s.sizePix);
  const double separation = 30.0 / s.pixelScaleArcsec;
  if (s.lensCount > 0 && !(s.sizePix - 1 - margin > margin)) {
    throw ConfigError("--lenses: a " + std::to_string(s.sizePix) + " x " +
                      std::to_string(s.sizePix) + " pixel field is too small for lens systems (" +
                      formatNumber(margin) + " pixels from every edge)");
  }
  std::mt19937_64 rng = streamRng(s.seed, kStreamLensPositions, 0);
  std::uniform_real_distribution<double> u(margin, s.sizePix - 1 - margin);
  std::vector<Vec2> positions;
  for (int attempt = 0; attempt < 200000 && int(positions.size()) < s.lensCount; ++attempt) {
    const Vec2 p{u(rng), u(rng)};
    if (p[0] > gapX0 - 0.5 * separation && p[0] < gapX1 + 0.5 * separation) continue;
    bool clear = true;
    for (const Vec2& q : positions) {
      if (std::hypot(p[0] - q[0], p[1] - q[1]) < separation) clear = false;
    }
    if (clear) positions.push_back(p);
  }
  if (int(positions.size()) < s.lensCount) {
    throw ConfigError("--lenses: " + std::to_string(s.lensCount) +
                      " lens systems do not fit in a " + std::to_string(s.sizePix) + " x " +
                      std::to_string(s.sizePix) +
                      " pixel field (30\" apart, away from the edges); only " +
                      std::to_string(positions.size()) + " placed");
  }
  return positions;
}

void printUsage() {
  std::cout
      << "Usage: octarc simulate field -o FIELD.fits [options]\n"
         "\n"
         "Simulates a survey-like image (default: 4096^2 pixels at 0.257\"/px, the Deep Lens\n"
         "Survey R-band setup): field galaxies with realistic number counts, sizes and\n"
         "morphologies (bright ellipticals with extended de Vaucouleurs haloes), stars down from\n"
         "saturation, Poisson sky noise, a TAN WCS and N injected galaxy-galaxy lenses. Writes\n"
         "FIELD.fits, FIELD.weight.fits (MAP_WEIGHT: 1/variance, a chip gap at half weight) and\n"
         "FIELD.truth.txt, an ASSOC list: id x y ra dec kind mag theta_E system\n"
         "(kind 1 = lens galaxy, 2 = lensed image, 3 = galaxy, 4 = star; x, y 1-based pixels).\n"
         "\n"
         "Options:\n";
}

po::options_description fieldOptions() {
  po::options_description o;
  auto add = o.add_options();
  add("help,h", "this help");
  add("output,o", po::value<std::string>(), "output image FIELD.fits");
  add("size", po::value<int>()->default_value(4096), "image side, pixels");
  add("pixel-scale", po::value<double>()->default_value(0.257, "0.257"), "arcsec per pixel");
  add("seeing", po::value<double>()->default_value(0.9, "0.9"), "PSF FWHM, arcsec");
  add("gain", po::value<double>()->default_value(54.0), "e-/ADU");
  add("noise-sigma", po::value<double>(), "sky noise per pixel, ADU");
  add("limiting-mag", po::value<double>()->default_value(26.0),
      "5-sigma limiting magnitude in a 2xFWHM aperture (sets the noise)");
  add("mag-zero", po::value<double>()->default_value(30.0), "magnitude zero point");
  add("saturate", po::value<double>()->default_value(30000.0), "saturation level, ADU");
  add("lenses", po::value<int>()->default_value(0), "number of injected lens systems");
  add("min-einstein-radius", po::value<double>()->default_value(0.0),
      "redraw lens systems with a smaller Einstein radius, arcsec");
  add("seed", po::value<std::uint64_t>()->default_value(1), "master random seed");
  add("ra", po::value<double>()->default_value(150.0), "RA of the field centre, deg");
  add("dec", po::value<double>()->default_value(2.0), "Dec of the field centre, deg");
  add("config", po::value<std::string>(),
      "octarc .sex file: PIXEL_SCALE, SEEING_FWHM, GAIN, MAG_ZEROPOINT, SATUR_LEVEL");
  add("database", po::value<std::string>(),
      "RealGalaxyCatalog FITS table of lensed source galaxies (default: synthetic)");
  add("population", po::value<std::string>(),
      "lens population file (default: simulation/population.txt of share/octarc)");
  add("threads", po::value<int>()->default_value(0), "worker threads (0 = all cores)");
  add("quiet", "no progress bar");
  return o;
}

// Boost would read a negative number after an option as an option of its own: glue the values
// of value-taking options to their names ("--lenses=-1"), so they reach the range checks.
std::vector<std::string> glueValues(const std::vector<std::string>& args,
                                    const po::options_description& options) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string name;
    if (a.rfind("--", 0) == 0 && a.find('=') == std::string::npos) {
      name = a.substr(2);
    } else if (a.size() == 2 && a[0] == '-' && a[1] != '-') {
      name = a.substr(1);
    }
    const po::option_description* d =
        name.empty() ? nullptr : options.find_nothrow(name, false, false, false);
    if (d && d->semantic()->max_tokens() > 0 && i + 1 < args.size()) {
      out.push_back("--" + d->long_name() + "=" + args[i + 1]);
      ++i;
    } else {
      out.push_back(a);
    }
  }
  return out;
}

}  // namespace

double FieldSimulationSettings::skySigmaAdu() const {
  if (noiseSigmaAdu) return *noiseSigmaAdu;
  return skySigmaFromLimitingMagnitude(limitingMag, magZeroPoint, 2.0 * seeingFwhmArcsec,
                                       pixelScaleArcsec);
}

void FieldSimulationSettings::validate() const {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw ConfigError(what);
  };
  require(sizePix >= 64 && sizePix <= 16384,
          "--size: must be between 64 and 16384 pixels, got " + std::to_string(sizePix));
  require(pixelScaleArcsec > 0.0 && pixelScaleArcsec <= 10.0,
          "--pixel-scale: must be in (0, 10] arcsec, got " + formatNumber(pixelScaleArcsec));
  require(seeingFwhmArcsec > 0.0 && seeingFwhmArcsec <= 20.0,
          "--seeing: must be in (0, 20] arcsec, got " + formatNumber(seeingFwhmArcsec));
  require(gainElectronsPerAdu > 0.0 && std::isfinite(gainElectronsPerAdu),
          "--gain: must be positive, got " + formatNumber(gainElectronsPerAdu));
  require(!noiseSigmaAdu || (*noiseSigmaAdu > 0.0 && std::isfinite(*noiseSigmaAdu)),
          "--noise-sigma: must be positive, got " + formatNumber(noiseSigmaAdu.value_or(0.0)));
  require(limitingMag > 10.0 && limitingMag < 40.0,
          "--limiting-mag: must be between 10 and 40, got " + formatNumber(limitingMag));
  require(std::isfinite(magZeroPoint) && magZeroPoint > 0.0 && magZeroPoint < 50.0,
          "--mag-zero: must be between 0 and 50, got " + formatNumber(magZeroPoint));
  require(saturationAdu > 0.0 && std::isfinite(saturationAdu),
          "--saturate: must be positive, got " + formatNumber(saturationAdu));
  require(lensCount >= 0 && lensCount <= 100000,
          "--lenses: must be between 0 and 100000, got " + std::to_string(lensCount));
  require(minEinsteinRadiusArcsec >= 0.0 && minEinsteinRadiusArcsec < 10.0,
          "--min-einstein-radius: must be in [0, 10) arcsec, got " +
              formatNumber(minEinsteinRadiusArcsec));
  require(raDeg >= 0.0 && raDeg < 360.0,
          "--ra: must be in [0, 360) deg, got " + formatNumber(raDeg));
  require(decDeg > -90.0 && decDeg < 90.0,
          "--dec: must be in (-90, 90) deg, got " + formatNumber(decDeg));
  require(threads >= 0 && threads <= 256,
          "--threads: must be between 0 (all cores) and 256, got " + std::to_string(threads));
  const double sigma = skySigmaAdu();
  require(sigma < saturationAdu, "--saturate: " + formatNumber(saturationAdu) +
                                     " ADU is below the sky noise (" + formatNumber(sigma) +
                                     " ADU)");
}

SimulatedField simulateField(const FieldSimulationSettings& s, const ProgressFn& progress) {
  s.validate();
  const int threads = resolveThreads(s.threads);
  const int n = s.sizePix;
  const double sigma = s.skySigmaAdu();
  SimulatedField field;
  field.skySigmaAdu = sigma;
  // A chip gap: a vertical strip with half the exposure (twice the variance).
  const int gapWidth = std::max(4, n / 128);
  field.gapX0 = n / 2 - gapWidth / 2;
  field.gapX1 = field.gapX0 + gapWidth;
  field.header = tanWcsHeader(n, n, s.pixelScaleArcsec, s.raDeg, s.decDeg);
  const std::optional<Wcs> wcs = Wcs::fromHeader(field.header, "simulated field");

  // Lens systems: drawn by the lens-simulation engine's population draw (one stream per
  // system), rendered here noise-free and before the PSF.
  const std::vector<Vec2> lensPositions = drawLensPositions(s, field.gapX0, field.gapX1);
  std::vector<FieldLens> lenses(lensPositions.size());
  if (!lenses.empty()) {
    SimulationSetup setup;
    setup.population = readPopulationModel(s.populationPath.empty() ? defaultPopulationModelPath()
                                                                    : s.populationPath);
    SyntheticGalaxyOptions sourceOptions;
    const SourceDatabase sources =
        s.databasePath.empty()
            ? SourceDatabase::synthetic(kSyntheticSources, systemSeed(s.seed, kStreamSources),
                                        sourceOptions)
            : SourceDatabase::fromRealGalaxyCatalog(s.databasePath);
    const std::uint64_t lensSeed = systemSeed(s.seed, kStreamLenses);
    parallelForDynamic(std::int64_t(lenses.size()), threads, [&](std::size_t i) {
      // Systems below the minimum Einstein radius are redrawn from the same stream.
      std::mt19937_64 rng = systemRng(lensSeed, i);
      LensSystemDraw draw = drawLensSystem(setup, sources, std::int64_t(i), rng);
      for (int tries = 1; draw.einsteinRadiusArcsec < s.minEinsteinRadiusArcsec; ++tries) {
        if (tries == kMaxLensRedraws) {
          throw ConfigError("--min-einstein-radius: no lens system with theta_E >= " +
                            formatNumber(s.minEinsteinRadiusArcsec) + "\" in " +
                            std::to_string(kMaxLensRedraws) + " draws of the population");
        }
        draw = drawLensSystem(setup, sources, std::int64_t(i), rng);
      }
      lenses[i] = renderFieldLens(draw.system, sources.stamp(draw.sourceIndex), lensPositions[i][0],
                                  lensPositions[i][1], s.pixelScaleArcsec, s.magZeroPoint);
    });
  }

  // Field objects, kept away from the lenses when bright.
  std::mt19937_64 populationRng = streamRng(s.seed, kStreamPopulation, 0);
  const std::vector<FieldObject> objects =
      drawFieldObjects(s.population, n, n, s.pixelScaleArcsec, populationRng, lensPositions,
                       15.0 / s.pixelScaleArcsec, 21.0);
  std::vector<std::size_t> galaxies, stars;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    (objects[i].kind == FieldObjectKind::Star ? stars : galaxies).push_back(i);
  }
  field.galaxyCount = std::int64_t(galaxies.size());
  field.starCount = std::int64_t(stars.size());
  const std::int64_t totalWork = std::int64_t(lenses.size() + objects.size()) + 1;
  std::int64_t doneWork = 0;
  auto report = [&](std::int64_t step) {
    doneWork += step;
    if (progress) progress(doneWork, totalWork);
  };

  ImageD sky(n, n);
  for (FieldLens& l : lenses) {
    addStamp(sky, l.stamp);
    l.stamp = Stamp{};
  }
  report(std::int64_t(lenses.size()));

  // Galaxies in batches: stamps rendered in parallel, summed in object order.
  std::vector<double> usedX(objects.size()), usedY(objects.size());
  for (std::size_t b = 0; b < galaxies.size(); b += kRenderBatch) {
    const std::size_t count = std::min(kRenderBatch, galaxies.size() - b);
    std::vector<Stamp> stamps(count);
    parallelForDynamic(std::int64_t(count), threads, [&](std::size_t k) {
      const std::size_t i = galaxies[b + k];
      std::mt19937_64 rng = streamRng(s.seed, kStreamGalaxies, i);
      stamps[k] = renderGalaxyStamp(objects[i], s.population, s.pixelScaleArcsec, s.magZeroPoint,
                                    rng, &usedX[i], &usedY[i]);
    });
    for (const Stamp& st : stamps) addStamp(sky, st);
    report(std::int64_t(count));
  }

  sky = convolveSeparable(sky, gaussianPsfKernel1d(s.seeingFwhmArcsec, s.pixelScaleArcsec));
  for (std::size_t i : stars) {
    const FieldObject& o = objects[i];
    addStamp(sky, renderStarStamp(o.xPix, o.yPix, fluxFromMagnitude(o.mag, s.magZeroPoint),
                                  s.seeingFwhmArcsec, s.pixelScaleArcsec, 0.01 * sigma));
    usedX[i] = o.xPix;
    usedY[i] = o.yPix;
  }
  report(std::int64_t(stars.size()));

  // Sky noise per band of rows, each band with its own stream; the gap gets a second, equal
  // noise (half the exposure doubles the variance).
  const std::int64_t bands = (n + kNoiseBandRows - 1) / kNoiseBandRows;
  field.image = ImageF(n, n);
  parallelForDynamic(bands, threads, [&](std::size_t band) {
    const std::int64_t y0 = std::int64_t(band) * kNoiseBandRows;
    const std::int64_t rows = std::min<std::int64_t>(kNoiseBandRows, n - y0);
    ImageD part(n, rows);
    std::copy_n(&sky(0, y0), n * rows, part.data());
    std::mt19937_64 rng = streamRng(s.seed, kStreamNoise, band);
    addPoissonSkyNoise(part, sigma, s.gainElectronsPerAdu, rng);
    std::mt19937_64 gapRng = streamRng(s.seed, kStreamGapNoise, band);
    std::normal_distribution<double> gapNoise(0.0, sigma);
    for (std::int64_t y = 0; y < rows; ++y)
      for (std::int64_t x = field.gapX0; x < field.gapX1; ++x) part(x, y) += gapNoise(gapRng);
    for (std::int64_t k = 0; k < part.size(); ++k) field.image[y0 * n + k] = float(part[k]);
  });
  sky = ImageD();
  field.saturatedPixels = clipSaturation(field.image, float(s.saturationAdu));
  field.weight = ImageF(n, n, float(1.0 / (sigma * sigma)));
  for (std::int64_t y = 0; y < n; ++y)
    for (std::int64_t x = field.gapX0; x < field.gapX1; ++x)
      field.weight(x, y) = float(0.5 / (sigma * sigma));
  report(1);  // the noise

  // The truth list: each lens system (lens galaxy, then its images), galaxies, stars.
  std::int64_t id = 0;
  auto addRow = [&](double x0, double y0, FieldObjectKind kind, double mag, double thetaE,
                    int system) {
    TruthRow r;
    r.id = ++id;
    r.xFits = toFitsPixel(x0);
    r.yFits = toFitsPixel(y0);
    const std::array<double, 2> world = wcs->pixelToWorld(r.xFits, r.yFits);
    r.raDeg = world[0];
    r.decDeg = world[1];
    r.kind = kind;
    r.mag = mag;
    r.einsteinRadiusArcsec = thetaE;
    r.systemId = system;
    field.truth.push_back(r);
  };
  for (std::size_t i = 0; i < lenses.size(); ++i) {
    const FieldLens& l = lenses[i];
    const double thetaE = l.system.mass.einsteinRadiusArcsec;
    addRow(l.xPix, l.yPix, FieldObjectKind::LensGalaxy, l.system.lensMag, thetaE, int(i) + 1);
    for (const FieldLens::LensedImage& im : l.images) {
      addRow(im.xPix, im.yPix, FieldObjectKind::LensedSource, im.mag, thetaE, int(i) + 1);
    }
  }
  for (std::size_t i : galaxies) {
    addRow(usedX[i], usedY[i], FieldObjectKind::Galaxy, objects[i].mag, 0.0, 0);
  }
  for (std::size_t i : stars)
    addRow(usedX[i], usedY[i], FieldObjectKind::Star, objects[i].mag, 0.0, 0);
  field.lenses = std::move(lenses);

  FitsHeader& h = field.header;
  h.set("BUNIT", quoteFitsString("ADU"), "Sky-subtracted counts");
  h.set("GAIN", fitsRealValue(s.gainElectronsPerAdu, 10), "Detector gain (e-/ADU)");
  h.set("SATURATE", fitsRealValue(s.saturationAdu, 10), "Saturation level (ADU)");
  h.set("MAGZERO", fitsRealValue(s.magZeroPoint, 10), "Magnitude zero point");
  h.set("SEEING", fitsRealValue(s.seeingFwhmArcsec, 10), "PSF FWHM (arcsec), Gaussian");
  h.set("PIXSCALE", fitsRealValue(s.pixelScaleArcsec, 10), "Pixel scale (arcsec/pixel)");
  h.set("SKYSIGMA", fitsRealValue(sigma, 10), "Sky noise per pixel (ADU), outside the gap");
  h.set("SIMSEED", std::to_string(s.seed), "octarc simulate field master seed");
  h.set("NLENSES", std::to_string(s.lensCount), "Injected lens systems");
  h.set("OBJECT", quoteFitsString("octarc simulated field"));
  return field;
}

FieldOutputPaths FieldOutputPaths::fromImagePath(const std::string& imagePath) {
  std::string stem = imagePath;
  for (const char* suffix : {".fits", ".fit", ".FITS", ".FIT"}) {
    const std::string sfx(suffix);
    if (stem.size() > sfx.size() && stem.compare(stem.size() - sfx.size(), sfx.size(), sfx) == 0) {
      stem.resize(stem.size() - sfx.size());
      break;
    }
  }
  return {imagePath, stem + ".weight.fits", stem + ".truth.txt"};
}

void addFieldOutputs(OutputFiles& outputs, const FieldOutputPaths& paths) {
  outputs.add(paths.image);
  outputs.add(paths.weight);
  outputs.add(paths.truth);
}

void writeSimulatedField(const SimulatedField& field, const FieldSimulationSettings& s,
                         const FieldOutputPaths& paths, const OutputFiles& outputs,
                         std::size_t first) {
  outputs.write(first, [&](const std::string& path) {
    OutputImageHdu image;
    image.header = field.header;
    image.floatPixels = &field.image;
    writeImageFile(path, {image});
  });
  outputs.write(first + 1, [&](const std::string& path) {
    OutputImageHdu weight;
    weight.header = tanWcsHeader(s.sizePix, s.sizePix, s.pixelScaleArcsec, s.raDeg, s.decDeg);
    weight.header.set("BUNIT", quoteFitsString("ADU**-2"), "Inverse variance");
    weight.header.set("WGHTTYPE", quoteFitsString("MAP_WEIGHT"), "SExtractor WEIGHT_TYPE");
    weight.floatPixels = &field.weight;
    writeImageFile(path, {weight});
  });
  outputs.write(first + 2, [&](const std::string& path) {
    {
      std::ofstream f(path);
      if (!f) throw IoError(paths.truth + ": cannot create the truth list");
      f << "# octarc simulate field truth list (SExtractor ASSOC list): " << paths.image << "\n"
        << "# seed " << s.seed << ", " << s.sizePix << "x" << s.sizePix << " px of "
        << s.pixelScaleArcsec << "\", " << s.lensCount << " lens systems\n"
        << "# kind: 1 = lens galaxy, 2 = lensed image (arc), 3 = galaxy, 4 = star\n"
        << "# ASSOC_PARAMS " << kTruthColumnX << "," << kTruthColumnY << " ASSOC_DATA "
        << kTruthColumnId << "," << kTruthColumnKind << "," << kTruthColumnMag << ","
        << kTruthColumnEinsteinRadius << "," << kTruthColumnSystem << "\n"
        << "# 1 ID\n# 2 X_IMAGE [pixel]\n# 3 Y_IMAGE [pixel]\n# 4 ALPHA_J2000 [deg]\n"
        << "# 5 DELTA_J2000 [deg]\n# 6 KIND\n# 7 MAG [mag]\n# 8 THETA_E [arcsec]\n"
        << "# 9 SYSTEM\n";
      char line[256];
      for (const TruthRow& r : field.truth) {
        std::snprintf(line, sizeof line, "%8lld %10.3f %10.3f %12.7f %12.7f %d %8.4f %7.4f %5d\n",
                      static_cast<long long>(r.id), r.xFits, r.yFits, r.raDeg, r.decDeg,
                      int(r.kind), r.mag, r.einsteinRadiusArcsec, r.systemId);
        f << line;
      }
      f.flush();
      if (!f) throw IoError(paths.truth + ": write failed");
    }
  });
}

int runSimulateField(const std::vector<std::string>& args) {
  const po::options_description options = fieldOptions();
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(glueValues(args, options)).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string(e.what()) + " (see octarc simulate field -h)");
  }
  if (vm.count("help")) {
    printUsage();
    std::cout << options;
    return 0;
  }
  if (!vm.count("output")) throw ConfigError("-o/--output: the output image name is required");
  FieldSimulationSettings s;
  // Survey settings from an octarc .sex file, then the explicit command-line options.
  if (vm.count("config")) {
    const std::string path = vm["config"].as<std::string>();
    std::vector<std::string> warnings;
    const sexcompat::Config config =
        sexcompat::Config::load(sexcompat::octarcMeasureKeys(), path, {}, &warnings);
    if (config.isExplicit("PIXEL_SCALE") && config.getDouble("PIXEL_SCALE") > 0)
      s.pixelScaleArcsec = config.getDouble("PIXEL_SCALE");
    if (config.isExplicit("SEEING_FWHM")) s.seeingFwhmArcsec = config.getDouble("SEEING_FWHM");
    if (config.isExplicit("GAIN") && config.getDouble("GAIN") > 0)
      s.gainElectronsPerAdu = config.getDouble("GAIN");
    if (config.isExplicit("MAG_ZEROPOINT")) s.magZeroPoint = config.getDouble("MAG_ZEROPOINT");
    if (config.isExplicit("SATUR_LEVEL")) s.saturationAdu = config.getDouble("SATUR_LEVEL");
  }
  auto pick = [&](const char* name, double& target) {
    if (vm.count(name) && (!vm[name].defaulted() || !vm.count("config")))
      target = vm[name].as<double>();
  };
  pick("pixel-scale", s.pixelScaleArcsec);
  pick("seeing", s.seeingFwhmArcsec);
  pick("gain", s.gainElectronsPerAdu);
  pick("mag-zero", s.magZeroPoint);
  pick("saturate", s.saturationAdu);
  s.limitingMag = vm["limiting-mag"].as<double>();
  if (vm.count("noise-sigma")) {
    if (!vm["limiting-mag"].defaulted())
      throw ConfigError("--noise-sigma and --limiting-mag: give one of them, not both");
    s.noiseSigmaAdu = vm["noise-sigma"].as<double>();
  }
  s.sizePix = vm["size"].as<int>();
  s.lensCount = vm["lenses"].as<int>();
  s.minEinsteinRadiusArcsec = vm["min-einstein-radius"].as<double>();
  s.seed = vm["seed"].as<std::uint64_t>();
  s.raDeg = vm["ra"].as<double>();
  s.decDeg = vm["dec"].as<double>();
  s.threads = vm["threads"].as<int>();
  if (vm.count("database")) s.databasePath = vm["database"].as<std::string>();
  if (vm.count("population")) s.populationPath = vm["population"].as<std::string>();
  const bool quiet = vm.count("quiet") > 0;
  s.validate();

  const FieldOutputPaths paths = FieldOutputPaths::fromImagePath(vm["output"].as<std::string>());
  OutputFiles outputs;
  addFieldOutputs(outputs, paths);
  for (const char* input : {"config", "database", "population"}) {
    if (!vm.count(input)) continue;
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      refuseOutputOverInput(outputs[i].finalPath(), "-o", vm[input].as<std::string>(),
                            std::string("--") + input + " file");
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const SimulatedField field = simulateField(s, terminalProgress("field", "objects", quiet));
  writeSimulatedField(field, s, paths, outputs);
  outputs.commit();
  if (!quiet) {
    std::cerr
        << "> " << paths.image << ": " << s.sizePix << "x" << s.sizePix << " px, "
        << field.galaxyCount << " galaxies, " << field.starCount << " stars ("
        << field.saturatedPixels << " saturated pixels), " << field.lenses.size()
        << " lens systems, sky sigma " << formatNumber(field.skySigmaAdu) << " ADU, in "
        << formatNumber(
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
               "%.1f")
        << " s\n> " << paths.weight << ", " << paths.truth << "\n";
  }
  return 0;
}

}  // namespace octarc
