// `octarc search`: from a survey image to ranked lens candidates ready for inspection.
//
//   image --> detection in memory (or INPUT_CATALOG) --> searched area --> selection with the
//   occupation grid --> one candidate per object, its lens --> OUTPUT_DIR (search/SearchRun.h)

#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/core/Error.h"
#include "octarc/core/Progress.h"
#include "octarc/search/SearchRun.h"

namespace octarc {

namespace {

// clang-format off
void printSearchUsage() {
  std::cout <<
      "Usage: octarc search IMAGE [-c survey.sex] [-KEY value ...]\n"
      "       octarc search DETECT_IMAGE,MEASURE_IMAGE [-c survey.sex] [-KEY value ...]\n"
      "\n"
      "Detects and measures IMAGE at every level of the configuration, as octarc detect does\n"
      "(or reads the rows of an earlier run: INPUT_CATALOG; dual-image mode as in octarc detect\n"
      "-h, the stamps from the measurement image), and keeps the rows that are\n"
      "  - inside the searched area: the DS9 region file MASK_NAME (the union of its include\n"
      "    shapes, the whole image without any, minus its '-' exclude shapes: mask stars with\n"
      "    -circle), good weight pixels (WEIGHT_IMAGE, WEIGHT_THRESH), MASK_BORDER from the edges;\n"
      "  - above the S/N floor (SNR_ISO > SNR_MIN) and resolved (sqrt(2) SIZE_IMAGE >\n"
      "    RESOLVED_MIN arcsec);\n"
      "  - in a selected bin of the occupation grid GRID_NAME (octarc calibrate), and in the\n"
      "    grid's own search space.\n"
      "Rows of one object at several levels make one candidate (its best row, the levels it\n"
      "passed). Its lens is the galaxy on the arc's concave side nearest the centre of\n"
      "curvature, within LENS_RADIUS; theta_E is the arc-lens distance; no lens: a possible\n"
      "dark lens. Candidates are counted in each SEARCH_SPACE (NAME: cut ...).\n"
      "\n"
      "Colours (not with INPUT_CATALOG): COLOUR_IMAGE names images of other bands on the\n"
      "measurement image's pixel grid (same size and WCS), COLOUR_BAND their names, and\n"
      "COLOUR_ZEROPOINT their zero-points (default MAG_ZEROPOINT). Each is background-subtracted\n"
      "like the measurement image and measured in the arc's and the lens's isophotal\n"
      "footprints: MAG_B, LENS_MAG_B, ARC_COLOUR_B and LENS_COLOUR_B (B minus the measurement\n"
      "band). COLOUR_CUT B,MAX removes candidates whose arc colour minus lens colour in B\n"
      "exceeds MAX; candidates without a lens or a colour are kept. A primary arc with a\n"
      "counter-image of the same colour (DARK_PAIR_COLOUR: N sigma, floor) inside its circle\n"
      "of curvature on the far side of its centre, and no other object near that centre, is a\n"
      "dark-lens pair: no lens, CAND_FLAGS 1 + 32, the counter-image in SEC_X, SEC_Y.\n"
      "\n"
      "Lens light: LENS_LIGHT LOCAL or IMAGE fits a Sersic model to each bright galaxy\n"
      "(LENS_SELECT) and searches the residual too (LOCAL) or instead (IMAGE). LENS_LIGHT_BAND B\n"
      "fits the models in colour band B's image (a redder band, where a blue arc is faint; its\n"
      "seeing COLOUR_SEEING_FWHM, default SEEING_FWHM), scales each by the galaxy's flux ratio\n"
      "in its core and draws it with this image's seeing before subtracting it.\n"
      "\n"
      "OUTPUT_DIR (written whole, replacing an earlier search output of that name):\n"
      "  candidates.fits  FITS-LDAC catalog, the summary in its header (-dp lists the columns)\n"
      "  candidates.cat   the same as ASCII_HEAD\n"
      "  candidates.reg   DS9 regions: arc ellipse (3 A x 3 B), lens circle, number (fk5 with\n"
      "                   a WCS, else image)\n"
      "  stamps/NNNN.png  STAMP_SIZE arcsec stamps, North and East arrows, scale bar\n"
      "  stamps/NNNN.colour.png  with COLOUR_IMAGE, the colour composite (Lupton et al. 2004)\n"
      "  index.html       the vetting page (works offline): sort, filter, grade by click or\n"
      "                   keys (j/k, 1/2/3), export the grades as CSV for octarc grades\n"
      "  summary.txt      objects searched, area, candidates per search space and per deg2\n"
      "\n"
      "An image without a celestial WCS is searched in pixel coordinates (PIXEL_SCALE must then\n"
      "be set). A grid made for another pixel scale, seeing, depth or thresholds is warned of.\n"
      "\n"
      "Options:\n"
      "  -c FILE      configuration file (SExtractor .sex syntax; see share/octarc/octarc.sex)\n"
      "  -KEY value   override a configuration key (e.g. -GRID_NAME dls.grid.fits)\n"
      "  -d, -dd      print the default configuration (-dd: every key)\n"
      "  -dp          list the columns of the candidate catalog\n"
      "  -h           this help;  -v  version\n";
}
// clang-format on

}  // namespace

int runSearch(const std::vector<std::string>& args) {
  std::optional<LoadedRun> loaded =
      loadRun(args, {"search", printSearchUsage, printCandidateColumns}, searchKeys());
  if (!loaded) return 0;
  requireImages(loaded->settings, "search", true);
  SearchRunSettings settings = searchSettingsFromConfig(loaded->config, loaded->settings);
  const bool quiet = settings.run.quiet;
  const RunLog log = quiet ? RunLog() : [](const std::string& line) { std::cerr << line << "\n"; };

  const SearchRun run = searchImage(settings, log);
  writeSearchOutputs(run, settings, terminalProgress("Stamps", "stamps", quiet), log);
  if (quiet) return 0;  // as SExtractor's QUIET: nothing on stdout either
  for (const std::string& line : searchSummaryLines(run, settings)) std::cout << line << "\n";
  if (settings.writeStamps) {
    std::cout << "Open " << settings.outputDir << "/index.html to inspect them\n";
  }
  return 0;
}

}  // namespace octarc
