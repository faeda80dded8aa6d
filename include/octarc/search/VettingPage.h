// The vetting page of a search or of a batch survey: one self-contained HTML file (no network,
// no external script) over a candidate catalog as written (search/CandidateTable.h; a survey's
// with TILE and TILE_NUMBER). The candidates are embedded once, as JSON; a small script of the
// page draws them as cards with their stamps, in pages of kVettingCardsPerPage (images loaded
// lazily), sorted by LENS_SCORE or another key, filtered by minimum score and arcness, CAND_FLAGS
// bits, "no visible lens" (kCandidateDarkLens), tile and grade. Grades (lens / maybe / no) are set
// by click or keys (j / k move, 1 / 2 / 3 grade, 0 clears), kept in the browser's localStorage
// under the page's storage key, and exported as CSV: NUMBER,[TILE,TILE_NUMBER,]NAME,ALPHA_J2000,
// DELTA_J2000,GRADE, one line per graded candidate, which `octarc grades` merges back into the
// catalog. A catalog with a GRADE column (a graded one) gives the grades the page starts from
// when the browser holds none for it.
//
// State the tests read: the element id="count" has data-matching (candidates passing the
// filters) and data-page; #grid holds the cards of the page shown, each with data-number and
// data-grade; the export link id="export" gets the CSV as a data: URL when clicked.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "octarc/io/FitsTable.h"

namespace octarc {

constexpr int kVettingCardsPerPage = 200;

struct VettingPageInfo {
  std::string title;
  // Shown at the top, as given (the caller makes paths relative, never absolute).
  std::vector<std::string> summaryLines;
  // Links under the summary: text, then the target relative to the page.
  std::vector<std::pair<std::string, std::string>> links;
  // Per catalog row: the stamp PNG relative to the page ("" for none).
  std::vector<std::string> stampFiles;
  // Per catalog row: a FITS cut-out relative to the page ("" or absent for none).
  std::vector<std::string> cutoutFiles;
  // Per catalog row: a colour composite stamp ("" or absent for none), which a "colour stamps"
  // box of the page (shown when a row has one) puts in the place of the grey stamp.
  std::vector<std::string> colourStampFiles;
};

// The page. IoError (naming the table) when `candidates` lacks NUMBER or stampFiles has another
// length than its rows.
std::string vettingPageHtml(const FitsTable& candidates, const VettingPageInfo& info);

// The stamps of a catalog's rows as octarc writes them, relative to a page beside the catalog:
// stamps/NNNN.png by NUMBER; for a survey's catalog (with TILE and TILE_NUMBER)
// tiles/TILE/stamps/NNNN.png by TILE_NUMBER.
std::vector<std::string> catalogStampFiles(const FitsTable& candidates);

// The key under which the page keeps its grades: the title and a hash of the candidates'
// numbers, names and scores, so that another catalog (a rerun) starts ungraded.
std::string vettingStorageKey(const FitsTable& candidates, const std::string& title);

}  // namespace octarc
