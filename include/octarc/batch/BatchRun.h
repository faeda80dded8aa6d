// `octarc batch` as a library: the search of every tile of a survey (TASK SEARCH), or the
// measurement of every tile's SExtractor outputs (TASK MEASURE, as `octarc measure` does it,
// run/MeasureJob.h), on one machine or on the ranks of an MPI job, resumable, and the
// survey-level outputs. Interrupted (core/Interrupt.h),
// it says how many tiles it journaled and whether it wrote the survey outputs.
//
//   manifest (batch/Manifest.h) --> tiles still to do (batch/Journal.h)
//     --> each tile claimed, searched (search/SearchRun.h) into OUTPUT_DIR/tiles/NAME, written
//         whole, then journaled; the ranks take tiles as they become free (cluster/Cluster.h)
//     --> once every tile is done or failed: OUTPUT_DIR/candidates.fits (batch/SurveyMerge.h),
//         summary.txt and index.html (the survey index), written together.
//
// Runs that share OUTPUT_DIR at the same time (batches started at once, the tasks of a job array,
// several MPI jobs) share its tiles: a run searches a tile only once it holds the tile's claim
// (a lock on claims/NAME, batch/Journal.h) and no other run has journaled it since this run
// began; a tile claimed by another is left to it. The run whose `finished` line finds every
// tile done or failed writes the survey outputs; one that ends while another still searches a
// tile leaves them to that one, and says so.
//
// OUTPUT_DIR:
//   .octarc-batch      marks the directory as a batch's (an other non-empty one is refused)
//   journal.txt        what each run did (batch/Journal.h)
//   configuration.txt  the configuration the tiles are searched with (batch/BatchConfiguration.h),
//                      written by the first run; a run with another one is a ConfigError naming
//                      the keys that differ, or with RESTART Y moves journal.txt,
//                      configuration.txt, tiles/ and the survey outputs into earlier-N/ (the
//                      first N free) and starts over. Each run checks it again before each of
//                      its journal lines, and stops once another has set its tiles aside.
//   claims/NAME        the lock file of a tile's claim (empty; locked while a run searches it)
//   tiles/NAME/        the tile's search output (candidates, regions, stamps, vetting page)
//                      and area.fits, its searched area per block; its candidates.fits is
//                      FITS-LDAC whatever CATALOG_TYPE says, as the merge reads it back
//   candidates.fits    the survey's candidates (CATALOG_TYPE, FITS-LDAC by default),
//                      duplicates of overlaps removed
//   candidates.html    the survey's vetting page (search/VettingPage.h), the tiles' stamps
//   candidates.cat     candidates.fits as ASCII_HEAD
//   candidates.reg     a DS9 circle at each candidate's RA, Dec (fk5)
//   summary.txt        tiles done / failed / done earlier, area, candidates per search space
//   index.html         the survey index: every tile, its status and its vetting page
//
// TASK MEASURE: tiles/NAME/ holds the tile's catalog (its input catalog with octarc's columns
// appended, under the input's file name; or, APPEND_COLUMNS N, a new catalog NAME.cat) and the
// folder's marker; summary.txt, the only survey output, lists each tile's rows and seconds.
#pragma once

#include <string>
#include <vector>

#include "octarc/batch/BatchKeys.h"
#include "octarc/batch/Manifest.h"
#include "octarc/batch/SurveyMerge.h"
#include "octarc/cluster/Cluster.h"
#include "octarc/core/Progress.h"
#include "octarc/search/SearchRun.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

inline constexpr const char* kBatchMarkerFile = ".octarc-batch";
inline constexpr const char* kBatchMarkerText = "octarc batch output directory\n";

// Done and Failed by this run; DoneEarlier: done by an earlier run, or by another while this one
// ran; OtherTask: not this task's share; OtherRun: another run held its claim when this one came
// to it.
enum class TileState { Done, Failed, DoneEarlier, OtherTask, OtherRun };

struct TileReport {
  TileState state = TileState::OtherTask;
  std::string message;           // the error of a failed tile
  std::int64_t candidates = 0;   // TASK SEARCH
  std::int64_t catalogRows = 0;  // TASK MEASURE: the rows of the tile's catalog
  double seconds = 0.0;
  int rank = 0;
};

struct BatchReport {
  std::vector<Tile> tiles;
  std::vector<TileReport> reports;  // per tile, as this run left it
  int run = 0;                      // the journal's run number
  bool merged = false;              // the survey outputs were written by this run
  SurveyCandidates survey;          // when merged
  std::vector<std::string> summaryLines;
  std::int64_t failed() const;
};

// Runs the batch on `cluster` (every rank calls it). ConfigError / IoError for a bad manifest,
// configuration, OUTPUT_DIR or another configuration there, before any tile is searched; a tile's
// own trouble makes it failed, and the others go on. The report is complete on the root only.
BatchReport runBatch(const BatchSettings& settings, const Cluster& cluster, const RunLog& log);

}  // namespace octarc
