#include "octarc/simulation/engine/LensSimulation.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <utility>

#include "octarc/core/Error.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/MultipleImageRegion.h"
#include "octarc/simulation/RealGalaxyCatalog.h"
#include "octarc/simulation/Seeds.h"

namespace octarc {

namespace sim = octarc::simulation;

namespace {

double threadCpuSec() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The columns every detected object gets: position, isophotal photometry, shape and the
// octopole arc statistics, as `octarc detect` measures them.
const char* const kMeasuredNames[] = {
    "NUMBER",        "THRESH_LEVEL", "PARENT_NUMBER", "THRESHOLD",   "X_IMAGE",    "Y_IMAGE",
    "ISOAREA_IMAGE", "FLUX_ISO",     "FLUXERR_ISO",   "MAG_ISO",     "SNR_ISO",    "FLUX_MAX",
    "A_IMAGE",       "B_IMAGE",      "THETA_IMAGE",   "ELLIPTICITY", "SIZE_IMAGE", "E_IMAGE",
    "E1_IMAGE",      "E2_IMAGE",     "ARCNESS",       "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR",
    "ARC_SIDE",      "FLAGS",        "OCT_FLAGS"};

}  // namespace

void StageTimings::add(const StageTimings& o) {
  drawSec += o.drawSec;
  rayTraceSec += o.rayTraceSec;
  lensLightSec += o.lensLightSec;
  psfSec += o.psfSec;
  noiseSec += o.noiseSec;
  detectionSec += o.detectionSec;
  arcRulesSec += o.arcRulesSec;
}

double StageTimings::totalSec() const {
  return drawSec + rayTraceSec + lensLightSec + psfSec + noiseSec + detectionSec + arcRulesSec;
}

// ---------------------------------------------------------------------------------------------
// Source databases

void SourceDatabase::add(sim::SourceStamp stamp) {
  const double rh = sim::halfLightRadiusArcsec(stamp);
  if (!(sim::totalFlux(stamp) > 0.0) || !(rh > 0.0)) {
    throw ConfigError("source database " + description_ + ": stamp '" + stamp.name +
                      "' has no positive flux");
  }
  halfLight_.push_back(rh);
  stamps_.push_back(std::move(stamp));
}

SourceDatabase SourceDatabase::synthetic(int count, std::uint64_t seed,
                                         const sim::SyntheticGalaxyOptions& options) {
  if (count < 1) throw ConfigError("--sources: the synthetic database needs at least 1 galaxy");
  SourceDatabase db;
  db.description_ = "synthetic (" + std::to_string(count) + " galaxies)";
  db.syntheticExtent_ = options.stampHalfLightRadii;
  constexpr sim::GalaxyType kTypes[] = {sim::GalaxyType::Elliptical, sim::GalaxyType::Spiral,
                                        sim::GalaxyType::Irregular};
  for (int i = 0; i < count; ++i) {
    std::mt19937_64 rng = sim::systemRng(seed, std::uint64_t(i));
    sim::SourceStamp s = sim::makeSyntheticGalaxy(kTypes[i % 3], rng, options);
    s.name += " #" + std::to_string(i);
    db.add(std::move(s));
  }
  return db;
}

SourceDatabase SourceDatabase::fromRealGalaxyCatalog(const std::string& path) {
  const sim::RealGalaxyCatalog catalog = sim::RealGalaxyCatalog::load(path, true);
  if (catalog.size() == 0) throw IoError(path + ": the galaxy catalog has no rows");
  SourceDatabase db;
  db.description_ = path;
  for (std::size_t i = 0; i < catalog.size(); ++i) db.add(catalog.loadGalaxy(i));
  return db;
}

SourceDatabase SourceDatabase::fromStamps(std::vector<sim::SourceStamp> stamps,
                                          std::string description) {
  SourceDatabase db;
  db.description_ = std::move(description);
  if (stamps.empty()) throw ConfigError("source database " + db.description_ + " is empty");
  for (sim::SourceStamp& s : stamps) db.add(std::move(s));
  return db;
}

// ---------------------------------------------------------------------------------------------
// Population draw

double limitingMagnitude(const sim::ObservingSetup& observing) {
  // The inverse of simulation::skySigmaFromLimitingMagnitude: 5 sigma in a 2" aperture.
  const double scale = observing.grid.pixelScaleArcsec;
  const double pixels = std::numbers::pi * 1.0 * 1.0 / (scale * scale);
  return observing.magZeroPoint - 2.5 * std::log10(5.0 * observing.skySigmaAdu * std::sqrt(pixels));
}

double renderProbability(const SimulationSetup& setup, const LensSystemDraw& d) {
  if (d.einsteinRadiusArcsec < setup.population.skipEinsteinRadiusBelowArcsec) return 0.0;
  if (setup.sampling == Sampling::Plain) return 1.0;
  const ImportanceSampling& is = setup.importance;
  const double* c = is.coefficients;
  const double mLim = limitingMagnitude(setup.observing);
  const double logit =
      c[0] + c[1] * std::log(d.einsteinRadiusArcsec / setup.arcRules.minDistanceArcsec) +
      c[2] * (d.source.mag - mLim) +
      c[3] * std::log(d.source.halfLightArcsec / setup.observing.seeingFwhmArcsec) +
      c[4] * (d.lens.mag - mLim);
  // sqrt(1 / (1 + e^-x)), written so that it neither overflows nor loses a tiny p.
  const double sqrtP = logit > 0 ? 1.0 / std::sqrt(1.0 + std::exp(-logit))
                                 : std::exp(0.5 * logit) / std::sqrt(1.0 + std::exp(logit));
  return std::clamp(is.scale * sqrtP, is.floor, 1.0);
}

LensSystemDraw drawLensSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                              std::int64_t index, std::mt19937_64& rng,
                              std::optional<double> renderUniform) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  LensSystemDraw d;
  d.index = index;
  // Rejection sampling from one stream, so the run stays reproducible whatever the threads.
  const sim::PopulationModel& pop = setup.population;
  for (std::int64_t attempt = 0;; ++attempt) {
    if (attempt >= pop.maxLensAttempts) {
      throw ConfigError(pop.sourcePath + ": lens.max_attempts: no lens-source pair kept in " +
                        std::to_string(pop.maxLensAttempts) + " draws of system " +
                        std::to_string(index) +
                        " (lens magnitude window, sigma range and source redshifts)");
    }
    const std::optional<sim::LensDraw> lens = pop.drawLens(setup.cosmology, rng);
    if (!lens) {
      ++d.rejections;
      continue;
    }
    d.lens = *lens;
    d.sourceIndex = std::uniform_int_distribution<std::size_t>(0, sources.size() - 1)(rng);
    const std::optional<sim::SourceDraw> source =
        pop.drawSource(sources.stamp(d.sourceIndex).type, rng);
    if (!source) {
      ++d.redraws;
      continue;
    }
    d.source = *source;
    const double weight = pop.lensingWeight(d.lens.redshift, d.source.redshift, setup.cosmology);
    if (unit(rng) < weight) break;
    ++d.rejections;
  }
  const sim::SourceStamp& stamp = sources.stamp(d.sourceIndex);
  d.einsteinRadiusArcsec = sim::sisEinsteinRadiusArcsec(d.lens.sigmaKmPerS, d.lens.redshift,
                                                        d.source.redshift, setup.cosmology);
  d.skipped = d.einsteinRadiusArcsec < pop.skipEinsteinRadiusBelowArcsec;
  d.renderProbability = renderProbability(setup, d);
  if (setup.sampling == Sampling::Importance && !d.skipped) {
    if (!renderUniform) {
      throw ConfigError("importance sampling: system " + std::to_string(index) +
                        " was drawn without its render deviate");
    }
    d.rendered = *renderUniform < d.renderProbability;
  } else {
    d.rendered = !d.skipped;
  }
  d.lensEllipticity =
      setup.lensEllipticityMin + (setup.lensEllipticityMax - setup.lensEllipticityMin) * unit(rng);
  const double paRad = std::numbers::pi * unit(rng);
  const double reArcsec = setup.lensHalfLightMinArcsec +
                          (setup.lensHalfLightMaxArcsec - setup.lensHalfLightMinArcsec) * unit(rng);

  sim::LensSystem& sys = d.system;
  sys.mass.einsteinRadiusArcsec = d.einsteinRadiusArcsec;
  sys.mass.ellipticity = sim::potentialEllipticityFromLight(d.lensEllipticity);
  sys.mass.coreArcsec = setup.lensCoreArcsec;
  sys.mass.positionAngleRad = paRad;
  sys.light.sersicIndex = 4.0;
  sys.light.halfLightRadiusArcsec = reArcsec;
  sys.light.axisRatio = 1.0 - d.lensEllipticity;
  sys.light.positionAngleRad = paRad;
  sys.lensMag = d.lens.mag;
  if (setup.sampling == Sampling::Importance && !d.rendered) {
    // Not rendered: the source is not placed (its position costs more than the rest). A plain
    // draw places it even when skipped, so that a caller redrawing from the same stream (the
    // field simulator) sees the draws it always saw.
    const double nan = std::nan("");
    sys.source.betaArcsec = {nan, nan};
    sys.source.rotationRad = nan;
    sys.source.pixelScaleArcsec = nan;
    sys.sourceMag = d.source.mag;
    return d;
  }
  // Uniform over the whole multiply-imaged region (bounded by the cut, which reaches beyond
  // theta_E along the minor axis, not by the Einstein circle), so every system is strongly
  // lensed.
  sys.source.betaArcsec = sim::MultipleImageRegion(sys.mass).drawUniform(rng);
  sys.source.rotationRad = 2.0 * std::numbers::pi * unit(rng);
  // Resizing by pixel scale: the stamp keeps its pixels, each now covers more or less sky.
  sys.source.pixelScaleArcsec =
      stamp.pixelScaleArcsec * d.source.halfLightArcsec / sources.halfLightArcsec(d.sourceIndex);
  sys.sourceMag = d.source.mag;
  return d;
}

namespace {

double renderUniformOf(std::uint64_t masterSeed, std::int64_t index) {
  std::mt19937_64 rng = sim::renderRng(masterSeed, std::uint64_t(index));
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

}  // namespace

LensSystemDraw drawLensSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                              std::uint64_t masterSeed, std::int64_t index) {
  std::mt19937_64 rng = sim::systemRng(masterSeed, std::uint64_t(index));
  return drawLensSystem(setup, sources, index, rng, renderUniformOf(masterSeed, index));
}

// ---------------------------------------------------------------------------------------------
// Detection, measurement, arc rules

const std::vector<ColumnSpec>& measuredColumns() {
  return measuredPlan().columns();
}

const MeasurementPlan& measuredPlan() {
  static const MeasurementPlan plan = [] {
    std::vector<ColumnRequest> requests;
    for (const char* name : kMeasuredNames) requests.push_back({name, 1});
    std::vector<std::string> unknown;
    MeasurementPlan p = MeasurementPlan::build(requests, {}, &unknown);
    if (!unknown.empty()) throw Error("lens simulation: unknown measured column " + unknown[0]);
    return p;
  }();
  return plan;
}

Table detectAndMeasure(PreparedImage& image, const SimulationSetup& setup,
                       std::vector<std::int64_t>* levelCounts, StageTimings* timings,
                       std::optional<SegmentationRuns>* footprints) {
  const double t0 = timings ? threadCpuSec() : 0.0;
  const double sigmaAdu = setup.observing.skySigmaAdu;
  MeasureContext context =
      image.context(setup.observing.magZeroPoint, setup.observing.grid.pixelScaleArcsec);
  context.levels = levelsAtThresholds(setup.thresholdsAdu, sigmaAdu);
  DetectionRequest request;
  request.levels = context.levels;
  request.minAreaPix = setup.minAreaPix;
  request.threads = 1;
  request.footprintRuns = false;
  request.keepSegmentation = footprints != nullptr;
  ImageRunResult run = detectAndMeasure(image, measuredPlan(), context, request);
  Table table = run.rowsInCatalogOrder();
  if (timings) timings->detectionSec += threadCpuSec() - t0;
  if (levelCounts) *levelCounts = std::move(run.objectsPerLevel);
  if (footprints) *footprints = std::move(run.segmentation);
  return table;
}

PreparedImage prepareStamp(ImageF pixels, const SimulationSetup& setup) {
  InMemoryImage description;
  description.sigmaAdu = setup.observing.skySigmaAdu;
  description.gain = setup.observing.gainElectronsPerAdu;
  description.saturationAdu = setup.saturationAdu;
  description.filter = setup.filter ? &*setup.filter : nullptr;
  return prepareInMemory(std::move(pixels), description);
}

ArcSelection selectArcs(const Table& objects, double lensXPix, double lensYPix,
                        double pixelScaleArcsec, const ArcRules& rules, std::mt19937_64& rng) {
  const int cx = objects.requireColumn("X_IMAGE", "arc rules");
  const int cy = objects.requireColumn("Y_IMAGE", "arc rules");
  const int cs = objects.requireColumn("SIZE_IMAGE", "arc rules");
  const int cl = objects.requireColumn("THRESH_LEVEL", "arc rules");
  const int cf = objects.requireColumn("FLUX_ISO", "arc rules");
  ArcSelection out;
  const std::int64_t n = objects.rows();
  std::vector<bool> isArc(std::size_t(n), false);
  // Per level: number of objects and whether an arc is among them.
  std::vector<int> count;
  std::vector<bool> hasArc;
  for (std::int64_t r = 0; r < n; ++r) {
    // X_IMAGE/Y_IMAGE are 1-based.
    const double dx = objects.value(r, cx) - 1.0 - lensXPix;
    const double dy = objects.value(r, cy) - 1.0 - lensYPix;
    const double distance = std::hypot(dx, dy) * pixelScaleArcsec;
    out.distanceArcsec.push_back(distance);
    const double sizeArcsec = std::sqrt(2.0) * objects.value(r, cs) * pixelScaleArcsec;
    isArc[std::size_t(r)] = distance >= rules.minDistanceArcsec && sizeArcsec > rules.minSizeArcsec;
    const int level = int(objects.value(r, cl));
    if (level < 1) continue;
    if (std::size_t(level) > count.size()) {
      count.resize(std::size_t(level), 0);
      hasArc.resize(std::size_t(level), false);
    }
    ++count[std::size_t(level - 1)];
    if (isArc[std::size_t(r)]) hasArc[std::size_t(level - 1)] = true;
  }
  std::vector<int> qualifying;
  for (std::size_t k = 0; k < count.size(); ++k) {
    if (hasArc[k] && count[k] >= rules.minObjects) qualifying.push_back(int(k) + 1);
  }
  if (qualifying.empty()) return out;
  for (std::int64_t r = 0; r < n; ++r) {
    const int level = int(objects.value(r, cl));
    if (isArc[std::size_t(r)] &&
        std::find(qualifying.begin(), qualifying.end(), level) != qualifying.end()) {
      out.arcRows.push_back(r);
    }
  }
  const int chosenLevel =
      qualifying[std::uniform_int_distribution<std::size_t>(0, qualifying.size() - 1)(rng)];
  for (std::int64_t r : out.arcRows) {
    if (int(objects.value(r, cl)) != chosenLevel) continue;
    if (out.chosenRow < 0 || objects.value(r, cf) > objects.value(out.chosenRow, cf)) {
      out.chosenRow = r;
    }
  }
  return out;
}

RenderedSystem renderSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                            std::uint64_t masterSeed, std::int64_t index, StageTimings* timings) {
  const double t0 = timings ? threadCpuSec() : 0.0;
  RenderedSystem out;
  out.rng = sim::systemRng(masterSeed, std::uint64_t(index));
  out.draw = drawLensSystem(setup, sources, index, out.rng, renderUniformOf(masterSeed, index));
  // The second band's stream: the colours first, then its noise.
  std::mt19937_64 bandRng = sim::secondBandRng(masterSeed, std::uint64_t(index));
  if (setup.band) {
    std::normal_distribution<double> gauss(0.0, 1.0);
    const double zSource = gauss(bandRng);
    const double zLens = gauss(bandRng);
    out.sourceColourMag = setup.band->source.meanMag + setup.band->source.scatterMag * zSource;
    out.lensColourMag = setup.band->lens.meanMag + setup.band->lens.scatterMag * zLens;
  }
  if (timings) timings->drawSec += threadCpuSec() - t0;
  if (!out.draw.rendered) {
    // Skipped (cannot give an arc beyond the separation limit) or left out by the sampling.
    out.magnification = std::nan("");
    return out;
  }
  sim::RenderTimings render;
  const sim::SecondBandColours colours{out.sourceColourMag, out.lensColourMag, &bandRng};
  const sim::RenderedLensSystem rendered =
      sim::renderLensSystem(out.draw.system, sources.stamp(out.draw.sourceIndex), setup.observing,
                            out.rng, timings ? &render : nullptr, setup.band ? &colours : nullptr);
  out.magnification = rendered.magnification;
  if (timings) {
    timings->rayTraceSec += render.rayTraceSec;
    timings->lensLightSec += render.lensLightSec;
    timings->psfSec += render.psfSec;
    timings->noiseSec += render.noiseSec;
  }
  // The detector and the measurements read single precision, like a FITS image of BITPIX -32.
  out.image = ImageF(rendered.image.width(), rendered.image.height());
  for (std::int64_t i = 0; i < out.image.size(); ++i) out.image[i] = float(rendered.image[i]);
  if (setup.band) {
    out.bandImage = ImageF(rendered.bandImage.width(), rendered.bandImage.height());
    for (std::int64_t i = 0; i < out.bandImage.size(); ++i) {
      out.bandImage[i] = float(rendered.bandImage[i]);
    }
  }
  return out;
}

DetectedSystem detectSystem(ImageF image, const SimulationSetup& setup, std::mt19937_64& rng,
                            StageTimings* timings) {
  DetectedSystem out;
  const double tPrepare = timings ? threadCpuSec() : 0.0;
  out.prepared = prepareStamp(std::move(image), setup);
  if (timings) timings->detectionSec += threadCpuSec() - tPrepare;
  out.objects = detectAndMeasure(out.prepared, setup, &out.levelCounts, timings,
                                 setup.band ? &out.footprints : nullptr);
  const double t0 = timings ? threadCpuSec() : 0.0;
  const sim::SurveyGrid& grid = setup.observing.grid;
  out.arcs = selectArcs(out.objects, grid.lensXPix, grid.lensYPix, grid.pixelScaleArcsec,
                        setup.arcRules, rng);
  if (timings) timings->arcRulesSec += threadCpuSec() - t0;
  return out;
}

SecondBandMagnitudes measureSecondBand(const DetectedSystem& detected, const ImageF& bandImage,
                                       const SimulationSetup& setup) {
  if (!detected.footprints) throw Error("second band: the system's footprints were not kept");
  const SegmentationRuns& footprints = *detected.footprints;
  const sim::ObservingSetup& obs = setup.observing;
  BandImage measurement;
  measurement.pixels = &detected.prepared.hdu.pixels;
  measurement.sigmaAdu = obs.skySigmaAdu;
  measurement.gain = obs.gainElectronsPerAdu;
  measurement.magZeropoint = obs.magZeroPoint;
  BandImage band = measurement;  // the same noise level and zero point
  band.pixels = &bandImage;
  auto magnitudes = [&](const std::vector<PixelRun>& footprint) {
    return BandPair{isoMagnitude(measurement, footprint), isoMagnitude(band, footprint)};
  };

  // Each level's labels, rendered when first needed, and the object under the lens centre.
  std::map<int, ImageI32> labels;
  auto labelsOf = [&](int level) -> const ImageI32& {
    auto [it, added] = labels.try_emplace(level);
    if (added) footprints.render(level, it->second);
    return it->second;
  };
  const auto lensX = std::int64_t(std::lround(obs.grid.lensXPix));
  const auto lensY = std::int64_t(std::lround(obs.grid.lensYPix));
  auto lensAt = [&](int level) -> std::int32_t {
    const ImageI32& l = labelsOf(level);
    const bool inside = lensX >= 0 && lensY >= 0 && lensX < l.width() && lensY < l.height();
    return inside ? l(lensX, lensY) : 0;
  };
  auto footprintOf = [&](int level, std::int32_t number) {
    return footprints.footprints(level, {number}).front();
  };

  SecondBandMagnitudes out;
  const std::int32_t lensOne = lensAt(1);
  if (lensOne > 0) out.levelOneLens = magnitudes(footprintOf(1, lensOne));

  const Table& objects = detected.objects;
  const std::vector<std::int64_t>& arcRows = detected.arcs.arcRows;
  const int levelColumn = objects.requireColumn("THRESH_LEVEL", "second band");
  const int numberColumn = objects.requireColumn("NUMBER", "second band");
  out.arcs.resize(arcRows.size());
  out.lenses.resize(arcRows.size());
  for (std::size_t a = 0; a < arcRows.size(); ++a) {
    const int level = int(objects.value(arcRows[a], levelColumn));
    const auto number = std::int32_t(objects.value(arcRows[a], numberColumn));
    const std::vector<PixelRun> arc = footprintOf(level, number);
    out.arcs[a] = magnitudes(arc);
    // The levels nest: the level-1 lens holds the arc row when it holds any of its pixels.
    bool apartAtOne = lensOne > 0;
    const ImageI32& one = labelsOf(1);
    for (const PixelRun& run : arc) {
      for (std::int32_t x = run.x0; x <= run.x1 && apartAtOne; ++x) {
        if (one(x, run.y) == lensOne) apartAtOne = false;
      }
    }
    if (apartAtOne) {
      out.lenses[a] = out.levelOneLens;
      continue;
    }
    const std::int32_t lensHere = lensAt(level);
    if (lensHere > 0 && lensHere != number)
      out.lenses[a] = magnitudes(footprintOf(level, lensHere));
  }
  return out;
}

SimulatedSystem simulateSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                               std::uint64_t masterSeed, std::int64_t index, bool keepImage,
                               StageTimings* timings) {
  RenderedSystem rendered = renderSystem(setup, sources, masterSeed, index, timings);
  SimulatedSystem out;
  out.draw = std::move(rendered.draw);
  out.magnification = rendered.magnification;
  out.sourceColourMag = rendered.sourceColourMag;
  out.lensColourMag = rendered.lensColourMag;
  if (!out.draw.rendered) {
    out.objects = Table(measuredColumns());
    if (keepImage) out.image = ImageF(setup.observing.grid.width, setup.observing.grid.height);
    return out;
  }
  DetectedSystem detected = detectSystem(std::move(rendered.image), setup, rendered.rng, timings);
  if (setup.band) {
    const double t0 = timings ? threadCpuSec() : 0.0;
    out.band = measureSecondBand(detected, rendered.bandImage, setup);
    if (timings) timings->detectionSec += threadCpuSec() - t0;
  }
  out.levelCounts = std::move(detected.levelCounts);
  out.objects = std::move(detected.objects);
  out.arcs = std::move(detected.arcs);
  if (keepImage) out.image = std::move(detected.prepared.hdu.pixels);
  return out;
}

}  // namespace octarc
