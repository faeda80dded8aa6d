// `octarc simulate lenses`: N simulated galaxy-galaxy lenses through the detector and the
// measurements at the survey thresholds (METHOD.md section 3).
//
//   population draw --> ray trace + lens light + PSF + noise --> multi-threshold detection
//   --> measurements --> arc rules --> one row per system + every arc row --> FITS-LDAC file
//
// The work is simulation/engine/LensSetup.h (options -> setup) and LensCatalog.h (the run).

#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/batch/ClusterLenses.h"
#include "octarc/cluster/Cluster.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Progress.h"
#include "octarc/simulation/engine/LensCatalog.h"
#include "octarc/simulation/engine/LensSetup.h"
#include "octarc/simulation/engine/LensSimulation.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

namespace {

namespace po = boost::program_options;
namespace sim = octarc::simulation;

void printSimulateLensesUsage(const po::options_description& options) {
  std::cout
      << "Usage: octarc simulate lenses -n N --seed S -o OUT.fits [options]\n"
         "\n"
         "Simulates N galaxy-galaxy lenses (METHOD.md section 3), detects every stamp at\n"
         "the survey thresholds with octarc detect's code, measures every object and applies\n"
         "the arc rules. OUT.fits (FITS-LDAC) holds one row per system (truth and the chosen\n"
         "arc's measurements, LDAC_OBJECTS) and every arc row at every level (ARCS).\n"
         "With --band NAME each system is also made in a second band (simple colours, its\n"
         "own noise) and the arcs' and lens's colours are measured in the first band's\n"
         "footprints, as octarc search measures its candidates' colours.\n"
         "Survey settings come from built-in Deep Lens Survey defaults, then --config,\n"
         "then the options below. The output depends only on the seed, never on --threads,\n"
         "nor on the number of ranks when launched by mpirun or srun (the systems are then\n"
         "shared between the ranks, and the first rank writes OUT.fits).\n"
         "\n"
      << options << "\n";
}

template <typename T>
std::optional<T> optionValue(const po::variables_map& vm, const char* name) {
  if (vm.count(name)) return vm[name].as<T>();
  return std::nullopt;
}

// The options; those of the setup are stored straight into `o`.
po::options_description lensOptions(LensSetupOptions& o) {
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
    ("preset", po::value(&o.populationPreset)->value_name("NAME"), "lens population preset: "
     "physical (the default: a measured velocity dispersion function, cross-section weighted) "
     "or dls (the paper's Deep Lens Survey ranges)")
    ("population", po::value(&o.populationPath), "population relations file, instead of a "
     "preset (share/octarc/simulation/population*.txt)")
    ("threads", po::value<int>()->default_value(0), "worker threads (0 = all cores)")
    ("stamps", po::value<std::string>(), "also write the stamps of the first systems (FITS cube)")
    ("stamp-count", po::value<int>()->default_value(10), "systems in the stamps file")
    ("quiet", "no progress bar and no summary")
    ("pixel-scale", optionalValue(o.pixelScaleArcsec), "survey pixel scale, arcsec (default 0.257)")
    ("seeing", optionalValue(o.seeingFwhmArcsec), "Gaussian PSF FWHM, arcsec (default 0.9)")
    ("gain", optionalValue(o.gainElectronPerAdu), "gain, e-/ADU (default 54)")
    ("zero-point", optionalValue(o.magZeropoint), "magnitude zero point (default 30)")
    ("sky-sigma", optionalValue(o.skySigmaAdu), "per-pixel sky noise, ADU (default: from --limiting-mag)")
    ("limiting-mag", po::value(&o.limitingMag)->default_value(26.0),
     "5-sigma limiting magnitude in a 2\" aperture, sets the sky noise")
    ("stamp-size", po::value(&o.stampSizePix)->default_value(101), "stamp side, survey pixels")
    ("thresh", optionalValue(o.detectThreshold), "lowest level, sigma (default 2.5)")
    ("thresh-max", optionalValue(o.detectThresholdMax), "highest level, sigma (default 20)")
    ("nlevels", optionalValue(o.detectLevelCount), "number of levels (default 15)")
    ("minarea", optionalValue(o.minAreaPix), "DETECT_MINAREA, pixels (default 5)")
    ("lens-mag-min", optionalValue(o.lensMagMin), "lens magnitude window (default: the population file's)")
    ("lens-mag-max", optionalValue(o.lensMagMax), "")
    ("source-mag-min", optionalValue(o.sourceMagMin), "source magnitude range (default: the population file's)")
    ("source-mag-max", optionalValue(o.sourceMagMax), "")
    ("sigma-min", optionalValue(o.sigmaMinKmPerS), "velocity dispersion window, km/s (default: the population file's)")
    ("sigma-max", optionalValue(o.sigmaMaxKmPerS), "")
    ("lens-e-max", po::value(&o.lensEllipticityMax)->default_value(0.5), "largest lens light ellipticity")
    ("lens-rhalf-min", po::value(&o.lensHalfLightMinArcsec)->default_value(0.5), "lens half-light radius range, arcsec")
    ("lens-rhalf-max", po::value(&o.lensHalfLightMaxArcsec)->default_value(1.5), "")
    ("fine-scale", po::value(&o.fineScaleArcsec)->default_value(0.03), "ray-tracing grid step, arcsec")
    ("subsamples", po::value(&o.subSamples)->default_value(4), "rays per fine pixel along each axis")
    ("max-source-step", po::value(&o.maxSourceStepPixels)->default_value(1.0), "adaptive ray "
     "sampling: the fewest rays per fine pixel (up to --subsamples per axis) spaced at most this "
     "many source pixels apart on the source plane; 0: subsamples^2 rays everywhere")
    ("sampling", po::value<std::string>()->default_value("importance"), "importance: render each "
     "drawn system with a probability that favours those likely to give an arc, weighted back "
     "to the population (SIM_WEIGHT); plain: render every system (weight 1)")
    ("band", po::value<std::string>()->value_name("NAME"), "also simulate a second band NAME (e.g. g): "
     "the same systems with simple colours, measured in the first band's footprints (columns "
     "MAG_NAME, ARC_COLOUR_NAME, LENS_COLOUR_NAME, ...)")
    ("source-colour", po::value<std::string>()->value_name("MEAN,SCATTER"), "source colour "
     "m_NAME - m_measurement, Gaussian, mag (default 0.4,0.3: a blue star-forming source in g - r)")
    ("lens-colour", po::value<std::string>()->value_name("MEAN,SCATTER"), "lens colour, likewise "
     "(default 1.2,0.1: a red early-type lens in g - r)")
    ("timing", "print the CPU time per stage even with --quiet");
  // clang-format on
  return options;
}

// The source galaxies: a RealGalaxyCatalog, or the synthetic generator.
SourceDatabase sourceDatabase(const po::variables_map& vm) {
  if (vm.count("database")) {
    return SourceDatabase::fromRealGalaxyCatalog(vm["database"].as<std::string>());
  }
  sim::SyntheticGalaxyOptions galaxy;
  galaxy.stampHalfLightRadii = vm["source-extent"].as<double>();
  if (!(galaxy.stampHalfLightRadii > 0)) throw ConfigError("--source-extent must be positive");
  // A database of its own seed stream, so that the same sources serve every master seed.
  return SourceDatabase::synthetic(vm["sources"].as<int>(), kSyntheticSourceSeed, galaxy);
}

}  // namespace

int runSimulateLenses(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  LensSetupOptions o;
  const po::options_description options = lensOptions(o);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw ConfigError(std::string("simulate lenses: ") + e.what() + " (see -h)");
  }
  if (vm.count("help")) {
    printSimulateLensesUsage(options);
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
  if (vm.count("config")) {
    o.survey = readSurveySettings(vm["config"].as<std::string>());
    if (!quiet) {
      for (const std::string& w : o.survey->warnings) std::cerr << "WARNING: " << w << "\n";
    }
  }
  const std::string sampling = vm["sampling"].as<std::string>();
  if (sampling == "importance") {
    o.sampling = Sampling::Importance;
  } else if (sampling != "plain") {
    throw ConfigError("--sampling: '" + sampling + "' is neither importance nor plain");
  }
  if (vm.count("band")) o.bandName = vm["band"].as<std::string>();
  if (vm.count("source-colour")) {
    o.sourceColour = parseColourDraw(vm["source-colour"].as<std::string>(), "--source-colour");
  }
  if (vm.count("lens-colour")) {
    o.lensColour = parseColourDraw(vm["lens-colour"].as<std::string>(), "--lens-colour");
  }
  const SimulationSetup setup = makeSimulationSetup(o);

  const std::optional<std::string> stampsPath = optionValue<std::string>(vm, "stamps");
  const int stampCount =
      stampsPath ? int(std::min<std::int64_t>(vm["stamp-count"].as<int>(), count)) : 0;
  if (stampsPath && vm["stamp-count"].as<int>() < 1) {
    throw ConfigError("--stamp-count must be at least 1");
  }
  // Under mpirun or srun the systems are shared between the ranks; the root writes.
  const Cluster cluster;
  std::optional<SourceDatabase> sources;
  OutputFiles outputs;
  std::exception_ptr error;
  try {
    sources = sourceDatabase(vm);
    // The output names are checked before any system is simulated.
    if (cluster.isRoot()) {
      outputs.add(outPath);
      if (stampsPath) outputs.add(*stampsPath);
      for (const char* input : {"config", "database", "population"}) {
        if (!vm.count(input)) continue;
        for (std::size_t i = 0; i < outputs.size(); ++i) {
          refuseOutputOverInput(outputs[i].finalPath(), i == 0 ? "-o" : "--stamps",
                                vm[input].as<std::string>(), std::string("--") + input + " file");
        }
      }
    }
    // System 0 on this thread first: bad settings (e.g. a sigma range giving no lenses) fail
    // here with one message, before any thread starts.
    (void)drawLensSystem(setup, *sources, seed, 0);
  } catch (const Error&) {
    error = std::current_exception();
  }
  cluster.raiseIfAnyFailed(error);

  const int threads = cluster.threadsPerRank(vm["threads"].as<int>());
  LensRun lensRun;
  try {
    lensRun = runLensSimulationOnCluster(
        cluster, setup, *sources, seed, count, threads, stampCount,
        terminalProgress("simulating", "systems", quiet || !cluster.isRoot()));
    if (!cluster.isRoot()) return 0;
    // Both files are complete before either appears.
    outputs.write(0, [&](const std::string& path) {
      writeLensCatalog(path, lensRun, lensRunCards(lensRun, setup, *sources, seed));
    });
    if (stampsPath) {
      outputs.write(1, [&](const std::string& path) {
        writeLensStamps(path, lensRun, setup.observing.grid.pixelScaleArcsec);
      });
    }
    outputs.commit();
  } catch (const std::exception& e) {
    cluster.abortIfFailedAlone(e.what());  // the other ranks would wait for this one
    throw;
  }

  const StageTimings& total = lensRun.timings;
  const double wallSec =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!quiet || vm.count("timing")) {
    const double n = double(std::max<std::int64_t>(lensRun.rendered, 1));
    const double cpuSec = total.totalSec();
    std::fprintf(
        stderr,
        "> %lld systems drawn (%s sampling), %lld skipped (theta_E < %g\"), %lld rendered, "
        "sum of weights %.1f -> %s\n"
        "> %lld rendered with an arc, %.1f effective arcs (Kish), %lld arc rows\n"
        "> %lld lens-source pairs redrawn (the relations gave no source redshift)\n"
        "> wall %.1f s on %d rank(s) of %d thread(s); CPU %.1f s, %.2f effective arcs per "
        "CPU second; per rendered system: draw %.3f, ray trace %.3f, lens light %.3f, PSF %.3f, "
        "noise %.3f, detection and measurement %.3f, arc rules %.3f ms\n",
        static_cast<long long>(lensRun.drawn), sampling.c_str(),
        static_cast<long long>(lensRun.skipped), setup.population.skipEinsteinRadiusBelowArcsec,
        static_cast<long long>(lensRun.rendered), lensRun.weightSum, outPath.c_str(),
        static_cast<long long>(lensRun.systemsWithArc), lensRun.effectiveArcs(),
        static_cast<long long>(lensRun.arcs.rows()), static_cast<long long>(lensRun.redraws),
        wallSec, cluster.size(), threads, cpuSec,
        cpuSec > 0 ? lensRun.effectiveArcs() / cpuSec : 0.0, 1e3 * total.drawSec / n,
        1e3 * total.rayTraceSec / n, 1e3 * total.lensLightSec / n, 1e3 * total.psfSec / n,
        1e3 * total.noiseSec / n, 1e3 * total.detectionSec / n, 1e3 * total.arcRulesSec / n);
  }
  return 0;
}

}  // namespace octarc
