// `octarc simulate field`: options -> FieldSimulationSettings -> simulateField() ->
// writeSimulatedField() (simulation/engine/FieldSimulation.h).

#include <boost/program_options.hpp>
#include <chrono>
#include <iostream>

#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Progress.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/SurveySettings.h"

namespace octarc {

namespace po = boost::program_options;

namespace {

void printSimulateFieldUsage(const po::options_description& options) {
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
      << kOptionsAsKeys << "\nOptions:\n"
      << options;
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
  add("max-einstein-radius", po::value<double>()->default_value(0.0),
      "redraw lens systems with a larger theta_E, arcsec (0: none)");
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

}  // namespace

int runSimulateField(const std::vector<std::string>& args) {
  const po::options_description options = fieldOptions();
  const std::optional<ParsedOptions> parsed = parseOptions(
      args, {"simulate field", [&] { printSimulateFieldUsage(options); }, {}}, options);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->values;
  if (!vm.count("output")) throw ConfigError("-o/--output: the output image name is required");
  FieldSimulationSettings s;
  // Survey settings from an octarc .sex file, then the explicit command-line options.
  if (vm.count("config")) {
    const SurveySettings survey = readSurveySettings(vm["config"].as<std::string>());
    if (!vm.count("quiet")) {
      for (const std::string& w : survey.warnings) std::cerr << "WARNING: " << w << "\n";
    }
    applySurveySettings(s, survey);
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
  s.maxEinsteinRadiusArcsec = vm["max-einstein-radius"].as<double>();
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
