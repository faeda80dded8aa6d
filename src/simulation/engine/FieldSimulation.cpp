// A survey-like image with injected lenses, its weight map and a truth list (the engine of
// `octarc simulate field` and of the demo).
//
//   draws (one seeded stream) --> galaxy and lens stamps (threads, one stream each) --> sum
//   --> Gaussian PSF --> star stamps --> Poisson sky noise (per row band) --> saturation
//   --> FIELD.fits + FIELD.weight.fits + FIELD.truth.txt

#include "octarc/simulation/engine/FieldSimulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/Wcs.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/Noise.h"
#include "octarc/simulation/Psf.h"
#include "octarc/simulation/Seeds.h"
#include "octarc/simulation/engine/LensSimulation.h"

namespace octarc {

namespace sim = octarc::simulation;

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
  return sim::systemRng(sim::systemSeed(seed, stream), index);
}

// Synthetic source galaxies drawn from for the lensed sources (as `octarc simulate lenses`).
constexpr int kSyntheticSources = 60;
// Draws per lens system at most, to reach the minimum Einstein radius.
constexpr int kMaxLensRedraws = 100000;
// Objects rendered per batch: stamps of one batch are kept, then summed in order.
constexpr std::size_t kRenderBatch = 4096;
// Rows per noise band (each band has its own stream, so threads do not change the result).
constexpr std::int64_t kNoiseBandRows = 64;

// The injected lens systems, drawn by the lens-simulation engine's population draw (one
// stream per system; systems outside the Einstein-radius range are redrawn from the same
// stream), and the sources they lens.
struct LensDraws {
  SourceDatabase sources;
  std::vector<LensSystemDraw> draws;
  std::vector<double> reachArcsec;  // per system, how far its lensed light can reach
};

LensDraws drawLenses(const FieldSimulationSettings& s, int threads) {
  if (s.lensCount <= 0) return {};
  // A survey field: the lenses of the Deep Lens Survey preset unless told otherwise.
  SimulationSetup setup;
  setup.population = sim::readPopulationModel(
      s.populationPath.empty() ? sim::populationPresetPath("dls") : s.populationPath);
  sim::SyntheticGalaxyOptions sourceOptions;
  LensDraws out{s.databasePath.empty()
                    ? SourceDatabase::synthetic(
                          kSyntheticSources, sim::systemSeed(s.seed, kStreamSources), sourceOptions)
                    : SourceDatabase::fromRealGalaxyCatalog(s.databasePath),
                std::vector<LensSystemDraw>(std::size_t(std::max(s.lensCount, 0))),
                std::vector<double>(std::size_t(std::max(s.lensCount, 0)))};
  const std::uint64_t lensSeed = sim::systemSeed(s.seed, kStreamLenses);
  parallelForDynamic(std::int64_t(out.draws.size()), threads, [&](std::size_t i) {
    std::mt19937_64 rng = sim::systemRng(lensSeed, i);
    LensSystemDraw draw = drawLensSystem(setup, out.sources, std::int64_t(i), rng);
    auto outside = [&](double thetaE) {
      return thetaE < s.minEinsteinRadiusArcsec ||
             (s.maxEinsteinRadiusArcsec > 0 && thetaE > s.maxEinsteinRadiusArcsec);
    };
    for (int tries = 1; outside(draw.einsteinRadiusArcsec); ++tries) {
      if (tries == kMaxLensRedraws) {
        throw ConfigError("--min-einstein-radius, --max-einstein-radius: no lens system with " +
                          formatNumber(s.minEinsteinRadiusArcsec) + "\" <= theta_E" +
                          (s.maxEinsteinRadiusArcsec > 0
                               ? " <= " + formatNumber(s.maxEinsteinRadiusArcsec) + "\""
                               : std::string()) +
                          " in " + std::to_string(kMaxLensRedraws) + " draws of the population");
      }
      draw = drawLensSystem(setup, out.sources, std::int64_t(i), rng);
    }
    out.reachArcsec[i] =
        sim::lensedLightReachArcsec(draw.system, out.sources.stamp(draw.sourceIndex));
    out.draws[i] = std::move(draw);
  });
  return out;
}

// Lens centres: uniform, at least `margin` pixels inside the edges and off the chip gap, and so
// far apart that no two systems overlap: 30" or more, and more than the sum of the two systems'
// reaches (so that the lensed light of one never falls where the other's can).
std::vector<sim::Vec2> drawLensPositions(const FieldSimulationSettings& s, std::int64_t width,
                                         std::int64_t height, int gapX0, int gapX1,
                                         const std::vector<double>& reachArcsec) {
  const double margin = std::max(48.0, 0.06 * double(std::min(width, height)));
  const double separation = 30.0 / s.pixelScaleArcsec;
  if (s.lensCount > 0 && !(double(std::min(width, height)) - 1 - margin > margin)) {
    throw ConfigError("--lenses: a " + std::to_string(width) + " x " + std::to_string(height) +
                      " pixel field is too small for lens systems (" + formatNumber(margin) +
                      " pixels from every edge)");
  }
  std::mt19937_64 rng = streamRng(s.seed, kStreamLensPositions, 0);
  std::uniform_real_distribution<double> ux(margin, double(width) - 1 - margin);
  std::uniform_real_distribution<double> uy(margin, double(height) - 1 - margin);
  std::vector<sim::Vec2> positions;
  for (int attempt = 0; attempt < 200000 && int(positions.size()) < s.lensCount; ++attempt) {
    const sim::Vec2 p{ux(rng), uy(rng)};
    if (p[0] > gapX0 - 0.5 * separation && p[0] < gapX1 + 0.5 * separation) continue;
    bool clear = true;
    const std::size_t next = positions.size();
    for (std::size_t k = 0; k < next; ++k) {
      const double apart =
          std::max(separation, (reachArcsec[next] + reachArcsec[k]) / s.pixelScaleArcsec);
      if (std::hypot(p[0] - positions[k][0], p[1] - positions[k][1]) < apart) clear = false;
    }
    if (clear) positions.push_back(p);
  }
  if (int(positions.size()) < s.lensCount) {
    throw ConfigError("--lenses: " + std::to_string(s.lensCount) +
                      " lens systems do not fit in a " + std::to_string(width) + " x " +
                      std::to_string(height) +
                      " pixel field (30\" apart, never overlapping, away from the edges); only " +
                      std::to_string(positions.size()) + " placed");
  }
  return positions;
}

// The drawn systems rendered noise-free and before the PSF at their positions.
std::vector<sim::FieldLens> renderLenses(const FieldSimulationSettings& s, const LensDraws& drawn,
                                         const std::vector<sim::Vec2>& lensPositions, int threads) {
  std::vector<sim::FieldLens> lenses(lensPositions.size());
  parallelForDynamic(std::int64_t(lenses.size()), threads, [&](std::size_t i) {
    const LensSystemDraw& draw = drawn.draws[i];
    lenses[i] =
        renderFieldLens(draw.system, drawn.sources.stamp(draw.sourceIndex), lensPositions[i][0],
                        lensPositions[i][1], s.pixelScaleArcsec, s.magZeroPoint);
  });
  return lenses;
}

// Sky noise per band of rows, each band with its own stream; the gap gets a second, equal
// noise (half the exposure doubles the variance). Fills the image, the saturation and the
// weight map of `field` from the noise-free `sky`.
void addNoise(const FieldSimulationSettings& s, const ImageD& sky, int threads,
              SimulatedField& field) {
  const int n = s.sizePix;
  const double sigma = field.skySigmaAdu;
  const std::int64_t bands = (n + kNoiseBandRows - 1) / kNoiseBandRows;
  field.image = ImageF(n, n);
  parallelForDynamic(bands, threads, [&](std::size_t band) {
    const std::int64_t y0 = std::int64_t(band) * kNoiseBandRows;
    const std::int64_t rows = std::min<std::int64_t>(kNoiseBandRows, n - y0);
    ImageD part(n, rows);
    std::copy_n(&sky(0, y0), n * rows, part.data());
    std::mt19937_64 rng = streamRng(s.seed, kStreamNoise, band);
    sim::addPoissonSkyNoise(part, sigma, s.gainElectronsPerAdu, rng);
    std::mt19937_64 gapRng = streamRng(s.seed, kStreamGapNoise, band);
    std::normal_distribution<double> gapNoise(0.0, sigma);
    for (std::int64_t y = 0; y < rows; ++y)
      for (std::int64_t x = field.gapX0; x < field.gapX1; ++x) part(x, y) += gapNoise(gapRng);
    for (std::int64_t k = 0; k < part.size(); ++k) field.image[y0 * n + k] = float(part[k]);
  });
  field.saturatedPixels = sim::clipSaturation(field.image, float(s.saturationAdu));
  field.weight = ImageF(n, n, float(1.0 / (sigma * sigma)));
  for (std::int64_t y = 0; y < n; ++y)
    for (std::int64_t x = field.gapX0; x < field.gapX1; ++x)
      field.weight(x, y) = float(0.5 / (sigma * sigma));
}

// The truth list: each lens system (lens galaxy, then its images), galaxies, stars.
void addTruthRows(const std::vector<sim::FieldLens>& lenses,
                  const std::vector<sim::FieldObject>& objects,
                  const std::vector<std::size_t>& galaxies, const std::vector<std::size_t>& stars,
                  const std::vector<double>& usedX, const std::vector<double>& usedY,
                  const Wcs* wcs, SimulatedField& field) {
  std::int64_t id = 0;
  auto addRow = [&](double x0, double y0, sim::FieldObjectKind kind, double mag, double thetaE,
                    int system) {
    TruthRow r;
    r.id = ++id;
    r.xFits = toFitsPixel(x0);
    r.yFits = toFitsPixel(y0);
    const std::array<double, 2> world = wcs != nullptr
                                            ? wcs->pixelToWorld(r.xFits, r.yFits)
                                            : std::array<double, 2>{std::nan(""), std::nan("")};
    r.raDeg = world[0];
    r.decDeg = world[1];
    r.kind = kind;
    r.mag = mag;
    r.einsteinRadiusArcsec = thetaE;
    r.systemId = system;
    field.truth.push_back(r);
  };
  for (std::size_t i = 0; i < lenses.size(); ++i) {
    const sim::FieldLens& l = lenses[i];
    const double thetaE = l.system.mass.einsteinRadiusArcsec;
    addRow(l.xPix, l.yPix, sim::FieldObjectKind::LensGalaxy, l.system.lensMag, thetaE, int(i) + 1);
    for (const sim::FieldLens::LensedImage& im : l.images) {
      addRow(im.xPix, im.yPix, sim::FieldObjectKind::LensedSource, im.mag, thetaE, int(i) + 1);
    }
  }
  for (std::size_t i : galaxies) {
    addRow(usedX[i], usedY[i], sim::FieldObjectKind::Galaxy, objects[i].mag, 0.0, 0);
  }
  for (std::size_t i : stars)
    addRow(usedX[i], usedY[i], sim::FieldObjectKind::Star, objects[i].mag, 0.0, 0);
}

void setHeaderCards(const FieldSimulationSettings& s, FitsHeader& h) {
  const double sigma = s.skySigmaAdu();
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
}

}  // namespace

double FieldSimulationSettings::skySigmaAdu() const {
  if (noiseSigmaAdu) return *noiseSigmaAdu;
  return sim::skySigmaFromLimitingMagnitude(limitingMag, magZeroPoint, 2.0 * seeingFwhmArcsec,
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
  require(maxEinsteinRadiusArcsec == 0.0 ||
              (maxEinsteinRadiusArcsec > minEinsteinRadiusArcsec && maxEinsteinRadiusArcsec < 60.0),
          "--max-einstein-radius: must be 0 (none) or above --min-einstein-radius and below 60 "
          "arcsec, got " +
              formatNumber(maxEinsteinRadiusArcsec));
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
  field.header = sim::tanWcsHeader(n, n, s.pixelScaleArcsec, s.raDeg, s.decDeg);
  const std::optional<Wcs> wcs = Wcs::fromHeader(field.header, "simulated field");

  // Lens systems: drawn by the lens-simulation engine's population draw (one stream per
  // system), rendered here noise-free and before the PSF.
  const LensDraws drawn = drawLenses(s, threads);
  const std::vector<sim::Vec2> lensPositions =
      drawLensPositions(s, n, n, field.gapX0, field.gapX1, drawn.reachArcsec);
  std::vector<sim::FieldLens> lenses = renderLenses(s, drawn, lensPositions, threads);
  // Field objects, kept away from the lenses when bright.
  std::mt19937_64 populationRng = streamRng(s.seed, kStreamPopulation, 0);
  const std::vector<sim::FieldObject> objects =
      drawFieldObjects(s.population, n, n, s.pixelScaleArcsec, populationRng, lensPositions,
                       15.0 / s.pixelScaleArcsec, 21.0);
  std::vector<std::size_t> galaxies, stars;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    (objects[i].kind == sim::FieldObjectKind::Star ? stars : galaxies).push_back(i);
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
  for (sim::FieldLens& l : lenses) {
    sim::addStamp(sky, l.stamp);
    l.stamp = sim::Stamp{};
  }
  report(std::int64_t(lenses.size()));

  // Galaxies in batches: stamps rendered in parallel, summed in object order.
  std::vector<double> usedX(objects.size()), usedY(objects.size());
  for (std::size_t b = 0; b < galaxies.size(); b += kRenderBatch) {
    const std::size_t count = std::min(kRenderBatch, galaxies.size() - b);
    std::vector<sim::Stamp> stamps(count);
    parallelForDynamic(std::int64_t(count), threads, [&](std::size_t k) {
      const std::size_t i = galaxies[b + k];
      std::mt19937_64 rng = streamRng(s.seed, kStreamGalaxies, i);
      stamps[k] = renderGalaxyStamp(objects[i], s.population, s.pixelScaleArcsec, s.magZeroPoint,
                                    rng, &usedX[i], &usedY[i]);
    });
    for (const sim::Stamp& st : stamps) sim::addStamp(sky, st);
    report(std::int64_t(count));
  }

  // Every stamp summed so far already holds the flux per pixel (integrated or sub-sampled).
  sky = sim::applyGaussianSeeing(sky, s.seeingFwhmArcsec, s.pixelScaleArcsec);
  for (std::size_t i : stars) {
    const sim::FieldObject& o = objects[i];
    sim::addStamp(
        sky, sim::renderStarStamp(o.xPix, o.yPix, sim::fluxFromMagnitude(o.mag, s.magZeroPoint),
                                  s.seeingFwhmArcsec, s.pixelScaleArcsec, 0.01 * sigma));
    usedX[i] = o.xPix;
    usedY[i] = o.yPix;
  }
  report(std::int64_t(stars.size()));

  addNoise(s, sky, threads, field);
  sky = ImageD();
  report(1);  // the noise

  addTruthRows(lenses, objects, galaxies, stars, usedX, usedY, &*wcs, field);
  field.lenses = std::move(lenses);

  setHeaderCards(s, field.header);
  field.weightHeader = sim::tanWcsHeader(n, n, s.pixelScaleArcsec, s.raDeg, s.decDeg);
  field.weightHeader.set("BUNIT", quoteFitsString("ADU**-2"), "Inverse variance");
  field.weightHeader.set("WGHTTYPE", quoteFitsString("MAP_WEIGHT"), "SExtractor WEIGHT_TYPE");
  return field;
}

SimulatedField injectLenses(const ImageHdu& image, const ImageHdu* weight,
                            const FieldSimulationSettings& s) {
  constexpr double kNoInjectedLightAdu = 1e-6;
  s.validate();
  if (weight != nullptr && (weight->pixels.width() != image.pixels.width() ||
                            weight->pixels.height() != image.pixels.height())) {
    throw ConfigError("--into-weight: the weight map is " + std::to_string(weight->pixels.width()) +
                      " x " + std::to_string(weight->pixels.height()) + ", the image " +
                      std::to_string(image.pixels.width()) + " x " +
                      std::to_string(image.pixels.height()));
  }
  const int threads = resolveThreads(s.threads);
  const std::int64_t w = image.pixels.width(), h = image.pixels.height();
  SimulatedField field;
  field.header = image.header;
  field.gapX0 = field.gapX1 = -1000000;  // no chip gap
  const std::optional<Wcs> wcs = Wcs::fromHeader(image.header, "the image");
  const LensDraws drawn = drawLenses(s, threads);
  const std::vector<sim::Vec2> lensPositions =
      drawLensPositions(s, w, h, field.gapX0, field.gapX1, drawn.reachArcsec);
  std::vector<sim::FieldLens> lenses = renderLenses(s, drawn, lensPositions, threads);
  ImageD added(w, h);
  for (sim::FieldLens& l : lenses) {
    sim::addStamp(added, l.stamp);
    l.stamp = sim::Stamp{};
  }
  added = sim::applyGaussianSeeing(added, s.seeingFwhmArcsec, s.pixelScaleArcsec);
  // The injected light with its own photon noise (the image already holds the sky's).
  field.image = image.pixels;
  std::mt19937_64 rng = streamRng(s.seed, kStreamNoise, 0);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (std::int64_t k = 0; k < added.size(); ++k) {
    const double flux = added[k];
    // Only where light was added (the rest of the image stays exactly as it was).
    if (std::abs(flux) < kNoInjectedLightAdu) continue;
    const double noise = s.gainElectronsPerAdu > 0
                             ? std::sqrt(std::max(flux, 0.0) / s.gainElectronsPerAdu) * unit(rng)
                             : 0.0;
    field.image[k] = float(double(field.image[k]) + flux + noise);
  }
  // No saturation clip: the real image has its own level, and its pixels stay as they are.
  if (weight != nullptr) {
    field.weight = weight->pixels;
    field.weightHeader = weight->header;
  }
  addTruthRows(lenses, {}, {}, {}, {}, {}, wcs ? &*wcs : nullptr, field);
  field.lenses = std::move(lenses);
  field.header.set("NLENSES", std::to_string(s.lensCount), "Lens systems injected by octarc");
  field.header.set("SIMSEED", std::to_string(s.seed), "octarc injection master seed");
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
    // An image injected into without a weight map gets a uniform one (weights 1).
    const ImageF uniform =
        field.weight.empty() ? ImageF(field.image.width(), field.image.height(), 1.0f) : ImageF();
    OutputImageHdu weight;
    weight.header = field.weightHeader;
    weight.floatPixels = field.weight.empty() ? &uniform : &field.weight;
    writeImageFile(path, {weight});
  });
  outputs.write(first + 2, [&](const std::string& path) {
    {
      std::ofstream f(path);
      if (!f) throw IoError(paths.truth + ": cannot create the truth list");
      f << "# octarc simulate field truth list (SExtractor ASSOC list): " << paths.image << "\n"
        << "# seed " << s.seed << ", " << field.image.width() << "x" << field.image.height()
        << " px of " << s.pixelScaleArcsec << "\", " << s.lensCount << " lens systems\n"
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

void applySurveySettings(FieldSimulationSettings& s, const SurveySettings& survey) {
  s.pixelScaleArcsec = survey.pixelScaleArcsec.value_or(s.pixelScaleArcsec);
  s.seeingFwhmArcsec = survey.seeingFwhmArcsec.value_or(s.seeingFwhmArcsec);
  if (survey.gainElectronPerAdu && *survey.gainElectronPerAdu > 0) {
    s.gainElectronsPerAdu = *survey.gainElectronPerAdu;
  }
  s.magZeroPoint = survey.magZeropoint.value_or(s.magZeroPoint);
  s.saturationAdu = survey.saturationAdu.value_or(s.saturationAdu);
}

}  // namespace octarc
