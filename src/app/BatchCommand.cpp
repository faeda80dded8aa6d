// `octarc batch`: the search of every tile of a survey (or, TASK MEASURE, the measurement of
// every tile's SExtractor outputs), on one machine, on the ranks of an MPI job or as the tasks of
// a job array; resumable; the survey's candidates (or a summary of the tiles' catalogs) at the
// end.
//
//   manifest --> tiles not yet done (journal) --> each searched as `octarc search` does it
//   (or measured as `octarc measure` does it) --> OUTPUT_DIR/tiles/NAME --> survey candidates,
//   summary, index (batch/BatchRun.h)

#include <iostream>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/batch/BatchRun.h"
#include "octarc/cluster/Cluster.h"
#include "octarc/core/Error.h"
#include "octarc/search/CandidateTable.h"

namespace octarc {

namespace {

// clang-format off
void printBatchUsage() {
  std::cout <<
      "Usage: octarc batch MANIFEST [-c survey.sex] [-KEY value ...]\n"
      "       mpirun -np N octarc batch MANIFEST ...     (or srun octarc batch ...)\n"
      "\n"
      "Searches every tile of MANIFEST as octarc search does (detection, selection,\n"
      "candidates, stamps), then merges the tiles' candidates into the survey's.\n"
      "\n"
      "MANIFEST: one tile per line, IMAGE [WEIGHT [MASK [CATALOG]]], separated by commas or\n"
      "blanks ('-' for none, relative paths from the manifest's folder); a line starting\n"
      "with '#' is a comment; a path with commas, blanks, '#' or quotes is quoted as in CSV\n"
      "(\"a b, c.fits\", \"\" for a quote). WEIGHT is of the configuration's WEIGHT_TYPE, MASK\n"
      "a DS9 region file (MASK_NAME), CATALOG an earlier detection run (INPUT_CATALOG). Or a\n"
      "quoted glob of images: 'tiles/*.fits', where NAME.weight.fits is NAME.fits's weight\n"
      "map (with a WEIGHT_TYPE), not a tile. Tiles are named by their image file.\n"
      "\n"
      "-TASK MEASURE measures each tile as octarc measure does, on SExtractor's outputs: the\n"
      "manifest's rows are IMAGE SEGMENTATION CATALOG [WEIGHT] (the image, its SEGMENTATION\n"
      "check-image, its FITS_LDAC or FITS_1.0 catalog, its weight map). Each catalog is\n"
      "written with octarc's columns appended (APPEND_COLUMNS Y, its format kept) or anew\n"
      "(APPEND_COLUMNS N, CATALOG_TYPE) into OUTPUT_DIR/tiles/NAME/, with the same journal,\n"
      "resume, claims, MPI and job arrays; summary.txt lists each tile's rows and seconds.\n"
      "The search's own keys (GRID_NAME, MATCH_RADIUS, ...) are not used then.\n"
      "\n"
      "Launched by mpirun or srun (srun --mpi=pmix --cpus-per-task=$SLURM_CPUS_PER_TASK), the\n"
      "tiles are shared between the ranks as each becomes free; the first rank writes the\n"
      "journal and the survey outputs. As a job array (sbatch --array=0-N-1), task I takes the\n"
      "tiles k with k % N == I (ARRAY_TASK AUTO: by its position in an evenly spaced array; a\n"
      "task of a list such as --array=3,17 takes any tile that no other task has). Runs into\n"
      "one OUTPUT_DIR at once share its tiles, none searched twice (OUTPUT_DIR/claims); the\n"
      "last to finish writes the survey outputs.\n"
      "\n"
      "Resumable: a tile's folder is written whole, then journaled; running the same command\n"
      "again searches only the tiles not done (after a crash, a killed rank or a cancelled\n"
      "job), and retries those that failed. A tile that fails does not stop the others; the\n"
      "exit status is then 1. Interrupted (Ctrl-C), it says how many tiles it journaled\n"
      "(kept for the rerun) and whether it wrote the survey outputs.\n"
      "\n"
      "The first run records its configuration (OUTPUT_DIR/configuration.txt: the keys that\n"
      "change a tile's search, and the content of the grid, model, parameter and filter\n"
      "files); a run with another one is an error naming the keys that differ, unless\n"
      "-RESTART Y, which sets the earlier tiles aside (OUTPUT_DIR/earlier-N) and starts over.\n"
      "\n"
      "OUTPUT_DIR (default survey):\n"
      "  journal.txt       what each run did: start, done, failed, finished lines\n"
      "  configuration.txt the configuration the tiles are searched with\n"
      "  claims/NAME       a tile's claim, locked while a run searches it\n"
      "  tiles/NAME/       the tile's search output (see octarc search -h) and area.fits\n"
      "  candidates.fits   the survey's candidates (FITS-LDAC): TILE, TILE_NUMBER and the\n"
      "                    tiles' columns; copies closer than MATCH_RADIUS arcsec in two tiles'\n"
      "                    overlap kept once (the one nearest its tile's centre)\n"
      "  summary.txt       tiles done, failed, skipped; the union of the searched areas;\n"
      "                    candidates per search space and per deg2\n"
      "  candidates.html   the survey's vetting page (as octarc search's index.html, with a\n"
      "                    tile filter; stamps linked from the tiles' folders)\n"
      "  candidates.cat    candidates.fits as ASCII_HEAD\n"
      "  candidates.reg    DS9 regions: a 2\" circle at each candidate's RA, Dec (fk5)\n"
      "  index.html        the survey index: every tile, its status, its vetting page\n"
      "\n"
      "Options:\n"
      "  -c FILE      configuration file (the keys of octarc search, and MATCH_RADIUS,\n"
      "               ARRAY_TASK, RESTART, TASK)\n"
      "  -KEY value   override a configuration key (e.g. -ARRAY_TASK 3/16)\n"
      "  -d, -dd      print the default configuration (-dd: every key)\n"
      "  -dp          list the columns of the survey's candidate catalog\n"
      "  -h           this help;  -v  version\n";
}
// clang-format on

// -dp: the survey's candidates (batch/SurveyMerge.h): NUMBER over the survey, TILE,
// TILE_NUMBER, then the tiles' candidate columns but their NUMBER.
void printSurveyCandidateColumns() {
  std::vector<ColumnSpec> columns(3);
  columns[0].name = "NUMBER";
  columns[0].description = "Candidate number over the survey, by LENS_SCORE";
  columns[1].name = "TILE";
  columns[1].description = "Tile the candidate was kept from (its folder tiles/TILE)";
  columns[2].name = "TILE_NUMBER";
  columns[2].description = "NUMBER of the candidate in its tile's catalog";
  for (const CandidateColumnSpec& c : candidateColumns({"B"})) {
    if (c.spec.name != "NUMBER") columns.push_back(c.spec);
  }
  printColumnList(columns);
}

}  // namespace

int runBatch(const std::vector<std::string>& args) {
  const Cluster cluster;
  // Every rank reads the command line alike; a bad one is said once, by the first rank.
  std::optional<LoadedRun> loaded;
  std::optional<BatchSettings> settings;
  std::exception_ptr error;
  try {
    loaded = loadRun(args, {"batch", printBatchUsage, printSurveyCandidateColumns}, batchKeys(),
                     "manifest", true);
    if (loaded) settings = batchSettingsFromConfig(loaded->config, loaded->settings);
  } catch (const Error&) {
    error = std::current_exception();
  }
  cluster.raiseIfAnyFailed(error);
  if (!loaded) return 0;
  const bool quiet = loaded->settings.quiet;
  const RunLog log = quiet ? RunLog() : [](const std::string& line) { std::cerr << line << "\n"; };
  if (log && cluster.isRoot()) {
    for (const std::string& w : settings->warnings) log("WARNING: " + w);
  }

  BatchReport report;
  try {
    report = runBatch(*settings, cluster, log);
  } catch (const PeerFailed&) {
    throw;
  } catch (const std::exception& e) {
    cluster.abortIfFailedAlone(e.what());
    throw;
  }
  if (!cluster.isRoot()) return 0;
  for (const std::string& line : report.summaryLines) std::cout << line << "\n";
  if (report.merged && settings->task == BatchTask::Search) {
    std::cout << "Open " << settings->outputDir << "/index.html for the tiles\n";
  }
  if (report.failed() > 0) {
    std::cerr << "octarc batch: " << report.failed()
              << " tile(s) failed (see above); run the same command again to retry them\n";
    return 1;
  }
  return 0;
}

}  // namespace octarc
