// `octarc inject`: completeness and purity of the search on the user's own image, measured by
// injecting simulated lenses.
//
//   image, configuration --> InjectionStudySettings --> runInjectionStudy
//   (search/InjectionStudy.h: search the image, inject, search again, match, curves, outputs)
//   --> the summary on stdout

#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/search/InjectionStudy.h"

namespace octarc {

namespace {

// clang-format off
void printInjectUsage() {
  std::cout <<
      "Usage: octarc inject IMAGE [-c survey.sex] [-KEY value ...]\n"
      "\n"
      "Measures how complete and how pure the search is on IMAGE itself. It searches IMAGE as\n"
      "octarc search does (the same configuration and keys), injects INJECT_NUMBER simulated\n"
      "galaxy-galaxy lenses of the population (INJECT_POPULATION, default the dls preset;\n"
      "theta_E between INJECT_THETA_MIN and INJECT_THETA_MAX) into a copy, at least 30\"\n"
      "apart and never overlapping, and searches that copy again. The injected light is\n"
      "convolved with a Gaussian PSF of SEEING_FWHM at the image's pixel scale (PIXEL_SCALE or\n"
      "its WCS), scaled by MAG_ZEROPOINT, with the photon noise of GAIN (or the header's).\n"
      "\n"
      "An injected lens is found when a candidate of the injected image is one of its arcs: a\n"
      "passing row within 2\" of one of its lensed images and at least 1\" from its lens (a\n"
      "candidate on the lens galaxy is no found arc). The candidates of IMAGE as it is are the\n"
      "spurious ones. As LENS_SCORE's threshold falls through every candidate's score, it\n"
      "gives the completeness (found / injected, overall and per theta_E bin <2\", 2-2.5\",\n"
      ">=2.5\" and arc-magnitude bin <22, 22-23, >=23, with Wilson 68.27% intervals) against the\n"
      "spurious candidates per deg2 of searched area (SCORE_MIN is not applied). The injected\n"
      "image's own candidates that are no injected arc are counted too, as a check.\n"
      "\n"
      "With both GRID_NAME and MODEL_NAME given, each image is searched once per method (the\n"
      "grid, SELECTION_METHOD GRID, and the lens model, TREES): one curve each, in one table and\n"
      "one plot; otherwise SELECTION_METHOD's alone.\n"
      "\n"
      "INJECT_DIR (written together, or not at all; an existing one is replaced only when an\n"
      "earlier octarc inject wrote it):\n"
      "  completeness.fits   one row per method and threshold: METHOD, SCORE_MIN, SPURIOUS,\n"
      "                      SPURIOUS_PER_DEG2, FOUND, INJECTED, COMPLETENESS, COMPL_LO,\n"
      "                      COMPL_HI, the same per bin (vector columns), the check's\n"
      "                      SPURIOUS_INJ_PER_DEG2\n"
      "  summary.txt         the table at <= 30, 100, 400 and 1000 spurious per deg2 and at every\n"
      "                      candidate (also on stdout)\n"
      "  completeness.png    completeness against spurious per deg2, one curve per method\n"
      "                      (CHECKPLOT_DEV: .png, .pdf, .svg, .ps or .eps)\n"
      "  injected.fits       the image with the lenses; injected.truth.txt their lenses and\n"
      "                      images; candidates.txt both images' candidates and their matches\n"
      "\n"
      "Options:\n"
      "  -c FILE      configuration file (SExtractor .sex syntax; the search's keys and INJECT_*)\n"
      "  -KEY value   override a configuration key (e.g. -INJECT_NUMBER 20 -INJECT_SEED 2\n"
      "               -INJECT_DIR out -GRID_NAME survey.grid.fits -MODEL_NAME survey.model.fits)\n"
      "  -d, -dd      print the default configuration (-dd: every key)\n"
      "  -dp          (no catalog of chosen columns: an error)\n"
      "  -h           this help;  -v  version\n";
}
// clang-format on

}  // namespace

int runInject(const std::vector<std::string>& args) {
  std::optional<LoadedRun> loaded =
      loadRun(args, {"inject", printInjectUsage, nullptr}, injectionKeys());
  if (!loaded) return 0;
  requireImages(loaded->settings, "inject", false);
  InjectionStudySettings settings = injectionSettingsFromConfig(loaded->config, loaded->settings);
  const bool quiet = settings.search.run.quiet;
  if (!quiet) settings.log = [](const std::string& line) { std::cerr << line << "\n"; };

  const InjectionStudy study = runInjectionStudy(settings);
  if (!quiet) printInjectionSummary(std::cout, settings, study);
  return 0;
}

}  // namespace octarc
