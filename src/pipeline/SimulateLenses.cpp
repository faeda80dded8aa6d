// `octarc simulate lenses`: N simulated galaxy-galaxy lenses through the detector and the
// measurements at the survey thresholds (METHOD.md section 3).
//
//   population draw --> ray trace + lens light + PSF + noise --> multi-threshold detection
//   --> measurements --> arc rules --> one row per system + every arc row --> FITS-LDAC file
//
// Systems run in parallel; each is reproducible from (seed, index) alone and its results are
// placed by index, so the output does not depend on the thread count.

#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Progress.h"
#include "octarc/io/FitsImage.h"
#include "octarc/pipeline/LensSimulation.h"
#include "octarc/pipeline/Pipeline.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/Levels.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/ConvFile.h"
#include "octarc/sexcompat/Keys.h"
#include "octarc/simulation/Noise.h"

namespace octarc {

namespace {

namespace po = boost::program_options;
namespace sim = octarc::simulation;

// What one system leaves for the output tables.
struct SystemResult {
  LensSystemDraw draw;
  double magnification = 0.0;
  std::int64_t objectCount = 0;
  std::vector<double> arcValues;  // arc rows, measuredColumns() each, in table order
  std::vector<double> arcDistanceArcsec;
  int chosenArc = -1;  // index into the arc rows
  ImageF image;        // kept for the stamps file only
  StageTimings timings;
};

ColumnSpec column(const char* name, ColumnType type, const char* format, const char* unit,
                  const char* description) {
  ColumnSpec c;
  c.name = name;
  c.type = type;
  c.printfFormat = format;
  c.unit = unit;
  c.description = description;
  return c;
}

// The truth columns of the systems table, then ARC_FOUND and the chosen arc's columns.
std::vector<ColumnSpec> systemColumns() {
  using T = ColumnType;
  std::vector<ColumnSpec> c = {
      column("SYSTEM", T::Int32, "%9d", "", "Index of the simulated system (seed stream)"),
      column("Z_LENS", T::Float32, "%8.4f", "", "Lens redshift"),
      column("Z_SOURCE", T::Float32, "%8.4f", "", "Source redshift"),
      column("SIGMA_V", T::Float32, "%8.2f", "km/s", "Lens velocity dispersion (Faber-Jackson)"),
      column("LENS_MAG", T::Float32, "%8.4f", "mag", "Lens apparent magnitude"),
      column("LENS_ABSMAG", T::Float32, "%8.4f", "mag", "Lens absolute magnitude"),
      column("LENS_ELLIPTICITY", T::Float32, "%8.4f", "", "Lens light ellipticity 1 - b/a"),
      column("LENS_EPSILON", T::Float32, "%8.5f", "", "Potential ellipticity 0.2 e/(0.6 + e)"),
      column("LENS_THETA", T::Float32, "%8.3f", "deg", "Lens position angle (CCW from x)"),
      column("LENS_RHALF", T::Float32, "%8.4f", "arcsec", "Lens light half-light radius"),
      column("EINSTEIN_RADIUS", T::Float32, "%8.4f", "arcsec", "SIS Einstein radius"),
      column("SOURCE_MAG", T::Float32, "%8.4f", "mag", "Unlensed source magnitude"),
      column("SOURCE_RHALF", T::Float32, "%8.4f", "arcsec", "Source half-light radius"),
      column("SOURCE_X", T::Float32, "%9.5f", "arcsec", "Source position beta_x from the lens"),
      column("SOURCE_Y", T::Float32, "%9.5f", "arcsec", "Source position beta_y from the lens"),
      column("SOURCE_ROTATION", T::Float32, "%8.3f", "deg", "Source stamp rotation (CCW)"),
      column("SOURCE_INDEX", T::Int32, "%6d", "", "Row of the source database"),
      column("SOURCE_TYPE", T::Int16, "%2d", "", "0 elliptical, 1 spiral, 2 irregular"),
      column("MAGNIFICATION", T::Float32, "%10.4f", "", "Traced source flux / unlensed flux"),
      column("N_OBJECTS", T::Int32, "%6d", "", "Objects detected over all levels"),
      column("N_ARC_ROWS", T::Int32, "%4d", "", "Arc rows over all qualifying levels"),
      column("ARC_FOUND", T::Int16, "%2d", "", "1 if an arc passed the arc rules"),
      column("LENS_DISTANCE", T::Float32, "%8.4f", "arcsec",
             "Distance of the chosen arc to the lens centre"),
  };
  for (const ColumnSpec& m : measuredColumns()) c.push_back(m);
  return c;
}

std::vector<ColumnSpec> arcColumns() {
  using T = ColumnType;
  std::vector<ColumnSpec> c = {
      column("SYSTEM", T::Int32, "%9d", "", "Index of the simulated system"),
      column("CHOSEN", T::Int16, "%2d", "", "1 for the system's chosen arc row"),
      column("LENS_DISTANCE", T::Float32, "%8.4f", "arcsec", "Distance to the lens centre"),
  };
  for (const ColumnSpec& m : measuredColumns()) c.push_back(m);
  return c;
}

void printUsage(const po::options_description& options) {
  std::cout
      << "Usage: octarc simulate lenses -n N --seed S -o OUT.fits [options]\n"
         "\n"
         "Simulates N galaxy-galaxy lenses (METHOD.md section 3), detects every stamp at\n"
         "the survey thresholds with octarc detect's code, measures every object and applies\n"
         "the arc rules. OUT.fits (FITS-LDAC) holds one row per system (truth and the chosen\n"
         "arc's measurements, LDAC_OBJECTS) and every arc row at every level (ARCS).\n"
         "Survey settings come from built-in Deep Lens Survey defaults, then --config,\n"
         "then the options below. The output depends only on the seed, never on --threads.\n"
         "\n"
      << options << "\n";
}

// Writes the systems table and the arc table into one FITS-LDAC file at the temporary path
// of `out` (the caller commits it together with the stamps).
void writeTables(const AtomicFile& out, const Table& systems, const Table& arcs,
                 const std::vector<std::string>& runCards) {
  writeLdacTables(out.tempPath(), runCards, {{"LDAC_OBJECTS", &systems}, {"ARCS", &arcs}});
}

// The stamps of the first systems as one float cube (NAXIS3 = system index).
void writeStampCube(const AtomicFile& out, const std::vector<SystemResult>& results, int count,
                    double pixelScaleArcsec) {
  std::vector<const ImageF*> planes;
  for (int k = 0; k < count; ++k) planes.push_back(&results[std::size_t(k)].image);
  FitsHeader header;
  char scale[32];
  std::snprintf(scale, sizeof scale, "%.6f", pixelScaleArcsec);
  header.set("PIXSCALE", scale, "arcsec/pixel");
  header.set("BUNIT", quoteFitsString("ADU"), "background-subtracted counts");
  header.set("COMMENT", "Plane k (1-based) is simulated system k - 1 of the catalog.");
  writeImageCube(out.tempPath(), planes, header);
}

template <typename T>
std::optional<T> optionValue(const po::variables_map& vm, const char* name) {
  if (vm.count(name)) return vm[name].as<T>();
  return std::nullopt;
}

void requireRange(double lo, double hi, const char* loName, const char* hiName) {
  if (!(lo < hi)) {
    std::ostringstream s;
    s << loName << " (" << lo << ") must be below " << hiName << " (" << hi << ")";
    throw ConfigError(s.str());
  }
}

}  // namespace

int runSimulateLenses(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  po::options_description options("Options");
  // clang-format off
  options.add_options()
    ("help,h", "this help")
    ("count,n", po::value<std::int64_t>(), "number of systems (required, > 0)")
    ("seed", po::value<std::uint64_t>()->default_value(1), "master seed")
    ("output,o", po::value<std::string>(), "output catalog (FITS-LDAC, required)")
    ("config", po::value<std::string>(), "survey settings from an octarc .sex file (PIXEL_SCALE, "
     "SEEING_FWHM, GAIN, MAG_ZEROPOINT, SATUR_LEVEL, DETECT_THRESH, DETECT_THRESH_MAX, "
     "DETECT_NLEVELS, DETECT_LEVELS, THRESH_TYPE, DETECT_MINAREA, FILTER, FILTER_NAME)")
    ("database", po::value<std::string>(), "source galaxies: a RealGalaxyCatalog FITS table "
     "(default: the built-in synthetic generator)")
    ("sources", po::value<int>()->default_value(90), "number of synthetic source galaxies")
    ("source-extent", po::value<double>()->default_value(4.0),
     "synthetic source stamp radius in half-light radii")
    ("population", po::value<std::string>(), "population relations file "
     "(default: simulation/population.txt of octarc's data directory, share/octarc)")
    ("threads", po::value<int>()->default_value(0), "worker threads (0 = all cores)")
    ("stamps", po::value<std::string>(), "also write the stamps of the first systems (FITS cube)")
    ("stamp-count", po::value<int>()->default_value(10), "systems in the stamps file")
    ("quiet", "no progress bar and no summary")
    ("pixel-scale", po::value<double>(), "survey pixel scale, arcsec (default 0.257)")
    ("seeing", po::value<double>(), "Gaussian PSF FWHM, arcsec (default 0.9)")
    ("gain", po::value<double>(), "gain, e-/ADU (default 54)")
    ("zero-point", po::value<double>(), "magnitude zero point (default 30)")
    ("sky-sigma", po::value<double>(), "per-pixel sky noise, ADU (default: from --limiting-mag)")
    ("limiting-mag", po::value<double>()->default_value(26.0),
     "5-sigma limiting magnitude in a 2\" aperture, sets the sky noise")
    ("stamp-size", po::value<int>()->default_value(101), "stamp side, survey pixels")
    ("thresh", po::value<double>(), "lowest level, sigma (default 2.5)")
    ("thresh-max", po::value<double>(), "highest level, sigma (default 20)")
    ("nlevels", po::value<int>(), "number of levels (default 15)")
    ("minarea", po::value<int>(), "DETECT_MINAREA, pixels (default 5)")
    ("lens-mag-min", po::value<double>(), "lens magnitude range (population file: 21)")
    ("lens-mag-max", po::value<double>(), "(population file: 23)")
    ("source-mag-min", po::value<double>(), "source magnitude range (population file: 22)")
    ("source-mag-max", po::value<double>(), "(population file: 25)")
    ("sigma-min", po::value<double>(), "velocity dispersion cut, km/s (population file: 250)")
    ("sigma-max", po::value<double>(), "(population file: 400)")
    ("lens-e-max", po::value<double>()->default_value(0.5), "largest lens light ellipticity")
    ("lens-rhalf-min", po::value<double>()->default_value(0.5), "lens half-light radius range, arcsec")
    ("lens-rhalf-max", po::value<double>()->default_value(1.5), "")
    ("fine-scale", po::value<double>()->default_value(0.03), "ray-tracing grid step, arcsec")
    ("subsamples", po::value<int>()->default_value(4), "rays per fine pixel along each axis")
    ("timing", "print the CPU time per stage even with --quiet");
  // clang-format on
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string("simulate lenses: ") + e.what() + " (see -h)");
  }
  if (vm.count("help")) {
    printUsage(options);
    return 0;
  }
  if (!vm.count("count")) throw ConfigError("simulate lenses: -n N is required (see -h)");
  if (!vm.count("output")) throw ConfigError("simulate lenses: -o OUT.fits is required (see -h)");
  const std::int64_t count = vm["count"].as<std::int64_t>();
  if (count < 1)
    throw ConfigError("-n: the number of systems must be positive, got " + std::to_string(count));
  const std::uint64_t seed = vm["seed"].as<std::uint64_t>();
  const std::string outPath = vm["output"].as<std::string>();
  const bool quiet = vm.count("quiet") > 0;

  // Survey: DLS defaults, then the .sex file, then explicit options.
  SimulationSetup setup;
  sim::ObservingSetup& obs = setup.observing;
  double threshLow = 2.5, threshHigh = 20.0;
  int levelCount = 15;
  std::vector<double> explicitLevels;
  bool relative = true;
  int minArea = 5;
  if (vm.count("config")) {
    const std::string path = vm["config"].as<std::string>();
    std::vector<std::string> warnings;
    const sexcompat::Config config =
        sexcompat::Config::load(sexcompat::octarcMeasureKeys(), path, {}, &warnings);
    const RunSettings s = settingsFromConfig(config);
    // Only keys the file sets replace the survey defaults: SExtractor's own defaults (zero
    // point 0, gain 0 = infinite, 1.2" seeing) would describe no survey.
    auto given = [&config](const char* key) { return config.isExplicit(key); };
    if (given("PIXEL_SCALE") && s.pixelScaleArcsec > 0) {
      obs.grid.pixelScaleArcsec = s.pixelScaleArcsec;
    }
    if (given("SEEING_FWHM")) obs.seeingFwhmArcsec = s.seeingFwhmArcsec;
    if (given("GAIN")) obs.gainElectronsPerAdu = s.gainElectronPerAdu;
    if (given("MAG_ZEROPOINT")) obs.magZeroPoint = s.magZeropoint;
    if (given("SATUR_LEVEL")) setup.saturationAdu = s.saturationAdu;
    if (given("DETECT_THRESH")) threshLow = s.detectThreshold;
    if (given("DETECT_THRESH_MAX")) threshHigh = s.detectThresholdMax;
    if (given("DETECT_NLEVELS")) levelCount = s.detectLevelCount;
    explicitLevels = s.detectLevels;
    relative = s.detectThresholdType == ThresholdType::Relative;
    if (given("DETECT_MINAREA")) minArea = s.minAreaPix;
    if (s.filter) setup.filter = sexcompat::readConvFile(resolveFilterFile(s.filterPath));
  }
  if (auto v = optionValue<double>(vm, "pixel-scale")) obs.grid.pixelScaleArcsec = *v;
  if (auto v = optionValue<double>(vm, "seeing")) obs.seeingFwhmArcsec = *v;
  if (auto v = optionValue<double>(vm, "gain")) obs.gainElectronsPerAdu = *v;
  if (auto v = optionValue<double>(vm, "zero-point")) obs.magZeroPoint = *v;
  if (auto v = optionValue<double>(vm, "thresh")) threshLow = *v, explicitLevels.clear();
  if (auto v = optionValue<double>(vm, "thresh-max")) threshHigh = *v, explicitLevels.clear();
  if (auto v = optionValue<int>(vm, "nlevels")) levelCount = *v, explicitLevels.clear();
  if (auto v = optionValue<int>(vm, "minarea")) minArea = *v;
  if (!(obs.grid.pixelScaleArcsec > 0)) throw ConfigError("--pixel-scale must be positive");
  if (!(obs.seeingFwhmArcsec > 0)) throw ConfigError("--seeing (SEEING_FWHM) must be positive");
  if (!(obs.gainElectronsPerAdu > 0)) {
    throw ConfigError("--gain (GAIN) must be positive: Poisson noise needs a finite gain");
  }
  if (minArea < 1) throw ConfigError("--minarea (DETECT_MINAREA) must be at least 1");
  const int stampSize = vm["stamp-size"].as<int>();
  if (stampSize < 9) throw ConfigError("--stamp-size must be at least 9 pixels");
  obs.grid.width = obs.grid.height = stampSize;
  obs.grid.lensXPix = obs.grid.lensYPix = 0.5 * (stampSize - 1);
  obs.skySigmaAdu = vm.count("sky-sigma") ? vm["sky-sigma"].as<double>()
                                          : sim::skySigmaFromLimitingMagnitude(
                                                vm["limiting-mag"].as<double>(), obs.magZeroPoint,
                                                2.0, obs.grid.pixelScaleArcsec);
  if (!(obs.skySigmaAdu > 0)) throw ConfigError("--sky-sigma must be positive");
  obs.rayTrace.fineScaleArcsec = vm["fine-scale"].as<double>();
  obs.rayTrace.subSamples = vm["subsamples"].as<int>();
  if (!(obs.rayTrace.fineScaleArcsec > 0)) throw ConfigError("--fine-scale must be positive");
  if (obs.rayTrace.subSamples < 1) throw ConfigError("--subsamples must be at least 1");

  // Levels: the same log spacing as octarc detect (DETECT_NLEVELS from DETECT_THRESH to
  // DETECT_THRESH_MAX); RELATIVE levels are multiples of the stamp's known sky sigma.
  std::vector<double> levels = explicitLevels;
  if (levels.empty()) {
    if (levelCount < 1) throw ConfigError("--nlevels (DETECT_NLEVELS) must be at least 1");
    if (levelCount > 1) {
      requireRange(threshLow, threshHigh, "--thresh (DETECT_THRESH)",
                   "--thresh-max (DETECT_THRESH_MAX)");
    }
    levels = logSpacedLevels(threshLow, threshHigh, levelCount);
  }
  for (double l : levels) {
    const double adu = relative ? l * obs.skySigmaAdu : l;
    if (!(adu > 0)) throw ConfigError("detection thresholds must be positive");
    setup.thresholdsAdu.push_back(adu);
  }
  setup.minAreaPix = minArea;

  // Population: the relations file, then the range options.
  setup.population =
      sim::readPopulationModel(vm.count("population") ? vm["population"].as<std::string>()
                                                      : sim::defaultPopulationModelPath());
  sim::PopulationModel& pop = setup.population;
  if (auto v = optionValue<double>(vm, "lens-mag-min")) pop.lensMagnitude.magMin = *v;
  if (auto v = optionValue<double>(vm, "lens-mag-max")) pop.lensMagnitude.magMax = *v;
  if (auto v = optionValue<double>(vm, "source-mag-min")) pop.sourceMagnitude.magMin = *v;
  if (auto v = optionValue<double>(vm, "source-mag-max")) pop.sourceMagnitude.magMax = *v;
  if (auto v = optionValue<double>(vm, "sigma-min")) pop.sigmaMinKmPerS = *v;
  if (auto v = optionValue<double>(vm, "sigma-max")) pop.sigmaMaxKmPerS = *v;
  requireRange(pop.lensMagnitude.magMin, pop.lensMagnitude.magMax, "--lens-mag-min",
               "--lens-mag-max");
  requireRange(pop.sourceMagnitude.magMin, pop.sourceMagnitude.magMax, "--source-mag-min",
               "--source-mag-max");
  requireRange(pop.sigmaMinKmPerS, pop.sigmaMaxKmPerS, "--sigma-min", "--sigma-max");
  setup.lensEllipticityMax = vm["lens-e-max"].as<double>();
  if (!(setup.lensEllipticityMax >= 0 && setup.lensEllipticityMax < 1)) {
    throw ConfigError("--lens-e-max must be in [0, 1)");
  }
  setup.lensHalfLightMinArcsec = vm["lens-rhalf-min"].as<double>();
  setup.lensHalfLightMaxArcsec = vm["lens-rhalf-max"].as<double>();
  if (!(setup.lensHalfLightMinArcsec > 0)) throw ConfigError("--lens-rhalf-min must be positive");
  requireRange(setup.lensHalfLightMinArcsec, setup.lensHalfLightMaxArcsec, "--lens-rhalf-min",
               "--lens-rhalf-max");

  const std::optional<std::string> stampsPath = optionValue<std::string>(vm, "stamps");
  const int stampCount =
      stampsPath ? int(std::min<std::int64_t>(vm["stamp-count"].as<int>(), count)) : 0;
  if (stampsPath && vm["stamp-count"].as<int>() < 1) {
    throw ConfigError("--stamp-count must be at least 1");
  }
  // The output names are checked before any system is simulated.
  OutputFiles outputs;
  outputs.add(outPath);
  if (stampsPath) outputs.add(*stampsPath);
  for (const char* input : {"config", "database", "population"}) {
    if (!vm.count(input)) continue;
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      refuseOutputOverInput(outputs[i].finalPath(), i == 0 ? "-o" : "--stamps",
                            vm[input].as<std::string>(), std::string("--") + input + " file");
    }
  }

  // Sources.
  SourceDatabase sources = [&] {
    if (vm.count("database")) {
      return SourceDatabase::fromRealGalaxyCatalog(vm["database"].as<std::string>());
    }
    sim::SyntheticGalaxyOptions galaxy;
    galaxy.stampHalfLightRadii = vm["source-extent"].as<double>();
    if (!(galaxy.stampHalfLightRadii > 0)) throw ConfigError("--source-extent must be positive");
    // A database of its own seed stream, so that the same sources serve every master seed.
    return SourceDatabase::synthetic(vm["sources"].as<int>(), 0x5EEDDA7AULL, galaxy);
  }();

  // System 0 on this thread first: bad settings (e.g. a sigma range giving no lenses) fail here
  // with one message, before any thread starts.
  (void)drawLensSystem(setup, sources, seed, 0);

  const int threads = resolveThreads(vm["threads"].as<int>());
  std::vector<SystemResult> results(static_cast<std::size_t>(count));
  const ProgressFn progress = terminalProgress("simulating", "systems", quiet);
  parallelForDynamic(
      count, threads,
      [&](std::int64_t i) {
        SystemResult& r = results[std::size_t(i)];
        SimulatedSystem s = simulateSystem(setup, sources, seed, i, i < stampCount, &r.timings);
        r.draw = std::move(s.draw);
        r.magnification = s.magnification;
        r.objectCount = s.objects.rows();
        for (std::size_t a = 0; a < s.arcs.arcRows.size(); ++a) {
          const std::int64_t row = s.arcs.arcRows[a];
          const double* values = s.objects.row(row);
          r.arcValues.insert(r.arcValues.end(), values, values + s.objects.rowWidth());
          r.arcDistanceArcsec.push_back(s.arcs.distanceArcsec[std::size_t(row)]);
          if (row == s.arcs.chosenRow) r.chosenArc = int(a);
        }
        r.image = std::move(s.image);
      },
      [&](std::int64_t done) {
        if (progress) progress(done, count);
      });

  // Tables, in system order.
  const int measuredWidth = measuredPlan().rowWidth();
  Table systems(systemColumns());
  Table arcs(arcColumns());
  std::int64_t found = 0, redraws = 0;
  for (const SystemResult& r : results) {
    redraws += r.draw.redraws;
    const LensSystemDraw& d = r.draw;
    double* row = systems.appendRow();
    const double nan = std::nan("");
    const double truth[] = {double(d.index),
                            d.lens.redshift,
                            d.source.redshift,
                            d.lens.sigmaKmPerS,
                            d.lens.mag,
                            d.lens.absoluteMag,
                            d.lensEllipticity,
                            d.system.mass.ellipticity,
                            d.system.mass.positionAngleRad * kDegPerRad,
                            d.system.light.halfLightRadiusArcsec,
                            d.einsteinRadiusArcsec,
                            d.source.mag,
                            d.source.halfLightArcsec,
                            d.system.source.betaArcsec[0],
                            d.system.source.betaArcsec[1],
                            d.system.source.rotationRad * kDegPerRad,
                            double(d.sourceIndex),
                            double(int(sources.stamp(d.sourceIndex).type)),
                            r.magnification,
                            double(r.objectCount),
                            double(r.arcDistanceArcsec.size()),
                            r.chosenArc >= 0 ? 1.0 : 0.0,
                            r.chosenArc >= 0 ? r.arcDistanceArcsec[std::size_t(r.chosenArc)] : nan};
    const int truthCount = int(sizeof truth / sizeof truth[0]);
    std::copy(truth, truth + truthCount, row);
    if (r.chosenArc >= 0) {
      ++found;
      std::copy_n(r.arcValues.data() + std::size_t(r.chosenArc) * std::size_t(measuredWidth),
                  measuredWidth, row + truthCount);
    } else {
      std::fill_n(row + truthCount, measuredWidth, nan);
    }
    for (std::size_t a = 0; a < r.arcDistanceArcsec.size(); ++a) {
      double* arcRow = arcs.appendRow();
      arcRow[0] = double(d.index);
      arcRow[1] = int(a) == r.chosenArc ? 1.0 : 0.0;
      arcRow[2] = r.arcDistanceArcsec[a];
      std::copy_n(r.arcValues.data() + a * std::size_t(measuredWidth), measuredWidth, arcRow + 3);
    }
  }

  std::vector<std::string> cards = {
      formatCard("OCTSEED", std::int64_t(seed), "Master seed of the simulation"),
      formatCard("OCTNSYS", std::int64_t(count), "Simulated systems"),
      formatCard("OCTNARC", found, "Systems with an arc"),
      formatCard("OCTPIXSC", RealValue(obs.grid.pixelScaleArcsec, RealFormat::Fixed),
                 "Pixel scale (arcsec)"),
      formatCard("OCTSEEIN", RealValue(obs.seeingFwhmArcsec, RealFormat::Fixed),
                 "PSF FWHM (arcsec)"),
      formatCard("OCTSKYSG", RealValue(obs.skySigmaAdu), "Sky noise sigma (ADU)"),
      formatCard("OCTGAIN", RealValue(obs.gainElectronsPerAdu), "Gain (e-/ADU)"),
      formatCard("OCTMAGZP", RealValue(obs.magZeroPoint, RealFormat::Fixed), "Zero point"),
      formatCard("OCTNLEV", std::int64_t(setup.thresholdsAdu.size()), "Detection levels"),
      formatCard("OCTTHLO", RealValue(setup.thresholdsAdu.front()), "Lowest level (ADU)"),
      formatCard("OCTTHHI", RealValue(setup.thresholdsAdu.back()), "Highest level (ADU)"),
      formatCard("OCTMINAR", std::int64_t(setup.minAreaPix), "DETECT_MINAREA"),
      formatCard("OCTSRCDB", sources.description().substr(0, 60), "Source database"),
      formatCard("OCTREDRW", redraws, "Lens-source pairs redrawn (no source redshift)"),
  };
  // Both files are complete before either appears.
  writeTables(outputs[0], systems, arcs, cards);
  if (stampsPath) writeStampCube(outputs[1], results, stampCount, obs.grid.pixelScaleArcsec);
  outputs.commit();

  StageTimings total;
  for (const SystemResult& r : results) total.add(r.timings);
  const double wallSec =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!quiet || vm.count("timing")) {
    const double n = double(count);
    std::fprintf(stderr,
                 "> %lld systems, %lld with an arc, %lld arc rows -> %s\n"
                 "> %lld lens-source pairs redrawn (the relations gave no source redshift)\n"
                 "> wall %.1f s on %d thread(s); CPU %.1f s = %.2f ms/system: draw %.3f, ray "
                 "trace %.3f, lens light %.3f, PSF %.3f, noise %.3f, detection and "
                 "measurement %.3f, arc rules %.3f ms/system\n",
                 static_cast<long long>(count), static_cast<long long>(found),
                 static_cast<long long>(arcs.rows()), outPath.c_str(),
                 static_cast<long long>(redraws), wallSec, threads, total.totalSec(),
                 1e3 * total.totalSec() / n, 1e3 * total.drawSec / n, 1e3 * total.rayTraceSec / n,
                 1e3 * total.lensLightSec / n, 1e3 * total.psfSec / n, 1e3 * total.noiseSec / n,
                 1e3 * total.detectionSec / n, 1e3 * total.arcRulesSec / n);
  }
  return 0;
}

}  // namespace octarc
