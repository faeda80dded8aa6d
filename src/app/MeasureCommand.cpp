// `octarc measure`: the measurement module on a SExtractor run's segmentation check-images.
//
//   image --> background/noise --> segmentation images (one per threshold, nested)
//         --> measurements --> catalog (new, or the SExtractor catalog(s) with columns appended)

#include <chrono>
#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/run/MeasureJob.h"
#include "octarc/run/RunKeys.h"

namespace octarc {

namespace {

void printMeasureUsage() {
  std::cout
      << "Usage: octarc measure IMAGE [-c config.sex] [-KEY value ...]\n"
         "\n"
         "Measures every object of SExtractor SEGMENTATION check-images (one per threshold, "
         "lowest\n"
         "first: -SEGMENTATION_NAME seg1.fits[,seg2.fits,...]) on IMAGE and writes a catalog with\n"
         "SExtractor's isophotal columns and octarc's octopole (arcness) columns. With\n"
         "-INPUT_CATALOG cat1.ldac[,...] the output is each SExtractor catalog with the requested\n"
         "octarc columns appended, joined by NUMBER (one CATALOG_NAME per input catalog).\n"
         "\n"
         "Options:\n"
         "  -c FILE      configuration file (SExtractor .sex syntax)\n"
         "  -KEY value   override a configuration key (e.g. -CATALOG_NAME out.cat)\n"
         "  -d, -dd      print the default configuration (-dd: every key)\n"
         "  -dp          list every catalog column with its description and unit\n"
         "  -h           this help;  -v  version\n";
}

}  // namespace

int runMeasure(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<LoadedRun> run =
      loadRun(args, {"measure", printMeasureUsage, printMeasuredColumns}, octarcKeys());
  if (!run) return 0;
  requireImages(run->settings, "measure", false);
  const RunLog log =
      run->settings.quiet ? RunLog() : [](const std::string& line) { std::cerr << line << "\n"; };
  (void)runMeasureJob(run->settings, run->config,
                      {commandLineText("measure", args), run->warnings, start}, log);
  return 0;
}

}  // namespace octarc
