// `octarc simulate lenses`: N simulated galaxy-galaxy lenses through the detector and the
// measurements at the survey thresholds (METHOD.md section 3).
//
//   population draw --> ray trace + lens light + PSF + noise --> multi-threshold detection
//   --> measurements --> arc rules --> one row per system + every arc row --> FITS-LDAC file
//
// The work is simulation/engine/LensSetup.h (options -> setup), batch/ClusterLenses.h (the run
// on one process or the ranks of an MPI job, the files) and LensCatalog.h (the summary).

#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/batch/ClusterLenses.h"
#include "octarc/cluster/Cluster.h"
#include "octarc/core/Error.h"
#include "octarc/core/Progress.h"
#include "octarc/simulation/engine/LensCatalog.h"
#include "octarc/simulation/engine/LensSetup.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

namespace {

namespace po = boost::program_options;

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
      << kOptionsAsKeys << "\n"
      << options << "\n";
}

// -dp: the systems table's columns, then the arc table's.
void printLensColumns() {
  std::cout << "# LDAC_OBJECTS: one row per system\n";
  printColumnList(lensSystemColumns());
  std::cout << "# ARCS: every arc row at every level\n";
  printColumnList(lensArcColumns());
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

}  // namespace

int runSimulateLenses(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  LensSetupOptions o;
  const po::options_description options = lensOptions(o);
  const std::optional<ParsedOptions> parsed = parseOptions(
      args, {"simulate lenses", [&] { printSimulateLensesUsage(options); }, printLensColumns},
      options);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->values;
  if (!vm.count("count")) throw ConfigError("simulate lenses: -n N is required (see -h)");
  if (!vm.count("output")) throw ConfigError("simulate lenses: -o OUT.fits is required (see -h)");
  LensJob job;
  job.count = vm["count"].as<std::int64_t>();
  if (job.count < 1) {
    throw ConfigError("-n: the number of systems must be positive, got " +
                      std::to_string(job.count));
  }
  job.seed = vm["seed"].as<std::uint64_t>();
  job.catalogPath = vm["output"].as<std::string>();
  const bool quiet = vm.count("quiet") > 0;

  // Survey: DLS defaults, then the .sex file, then explicit options.
  if (vm.count("config")) {
    o.survey = readSurveySettings(vm["config"].as<std::string>());
    if (!quiet) {
      for (const std::string& w : o.survey->warnings) std::cerr << "WARNING: " << w << "\n";
    }
  }
  const std::string sampling = vm["sampling"].as<std::string>();
  o.sampling = parseSampling(sampling);
  if (vm.count("band")) o.bandName = vm["band"].as<std::string>();
  if (vm.count("source-colour")) {
    o.sourceColour = parseColourDraw(vm["source-colour"].as<std::string>(), "--source-colour");
  }
  if (vm.count("lens-colour")) {
    o.lensColour = parseColourDraw(vm["lens-colour"].as<std::string>(), "--lens-colour");
  }
  const SimulationSetup setup = makeSimulationSetup(o);

  if (vm.count("stamps")) {
    if (vm["stamp-count"].as<int>() < 1) throw ConfigError("--stamp-count must be at least 1");
    job.stampsPath = vm["stamps"].as<std::string>();
    job.stampCount = int(std::min<std::int64_t>(vm["stamp-count"].as<int>(), job.count));
  }
  // Under mpirun or srun the systems are shared between the ranks; the root writes.
  const Cluster cluster;
  job.threadsPerRank = cluster.threadsPerRank(vm["threads"].as<int>());
  for (const char* input : {"config", "database", "population"}) {
    if (vm.count(input))
      job.inputs.emplace_back(std::string("--") + input, vm[input].as<std::string>());
  }
  const LensRun lensRun = runLensJob(
      cluster, setup,
      [&] {
        return makeSourceDatabase(vm.count("database") ? vm["database"].as<std::string>() : "",
                                  vm["sources"].as<int>(), vm["source-extent"].as<double>());
      },
      job, terminalProgress("simulating", "systems", quiet || !cluster.isRoot()));
  if (!cluster.isRoot()) return 0;
  if (!quiet || vm.count("timing")) {
    const double wallSec =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fputs(
        lensRunSummary(lensRun, setup,
                       {sampling, job.catalogPath, wallSec, cluster.size(), job.threadsPerRank})
            .c_str(),
        stderr);
  }
  return 0;
}

}  // namespace octarc
