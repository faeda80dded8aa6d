// The candidate catalog of a search: its columns, declared and filled in one place, as a
// FITS-LDAC objects table (with the search summary as header keywords) and as ASCII_HEAD text.
//
// One row per candidate, by probability (NUMBER 1 is the most probable). Positions are 1-based
// pixels (core/Conventions.h) and J2000 degrees; NaN where there is no WCS or no lens. Values
// of the catalog taken from the candidate's best row (MAG_ISO, ARCNESS, ...) are NaN when the
// catalog has no such column (0 in the integer columns THRESH_LEVEL, ARC_SIDE, FLAGS).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "octarc/core/Column.h"
#include "octarc/core/Table.h"
#include "octarc/io/FitsTable.h"
#include "octarc/search/Search.h"

namespace octarc {

// A column of the candidate table; `type` is ignored for the string columns (text = true).
// Every column has its unit and its IVOA UCD (those of the measurement for the columns copied
// from the catalog, SExtractor's for SExtractor's columns).
struct CandidateColumnSpec {
  ColumnSpec spec;
  bool text = false;
};

// Every column, in table order (for -dp and the writers): the fixed ones, then per colour band
// B: MAG_B, MAGERR_B, LENS_MAG_B, LENS_MAGERR_B, ARC_COLOUR_B, ARC_COLOURERR_B, LENS_COLOUR_B,
// LENS_COLOURERR_B (a colour is B minus the measurement band).
// `levelCount` is the length of the LEVELS vector (the run's number of threshold levels).
std::vector<CandidateColumnSpec> candidateColumns(const std::vector<std::string>& colourBands,
                                                  int levelCount = 1);

// Column name -> IVOA UCD, for the writers of the catalog types that hold UCDs.
std::map<std::string, std::string> candidateColumnUcds(const std::vector<std::string>& colourBands);

// LEVELS lists the levels at which a candidate's object passed, lowest first, in a vector of the
// run's number of levels; the elements after the last level hold this value (levels count from 1).
constexpr int kCandidateLevelsFill = 0;

// The LDAC_OBJECTS table of the candidates, with the summary as keywords: NCANDID, NROWSRCH,
// NOBJSRCH, NROWSEL, SRCHPIX, SRCHAREA (deg2, undefined without WCS), CANDDEG2, REJFRAC,
// NDARKPR (dark-lens pairs), NCOLBAND and COLBANDn (the colour bands), COLCUTBD and COLCUTMX (the
// colour cut, when set), NCOLCUT (candidates it removed), NSPACES, and per report space n:
// SPNAMEn, SPEXPRn, SPCANDn, SPDEG2n.
FitsTable candidateObjectsTable(const Table& catalog, const SearchResult& result,
                                const SearchSettings& settings);

// The same rows as SExtractor's ASCII_HEAD: "# %3d %-22.22s %-58.58s [unit]" lines, then one
// line per candidate. Text values are single words, as SExtractor ASCII readers split lines at
// blanks: a blank becomes '_' ("OCTARC_J095951.45+015833.5") and an empty value "-".
std::string candidateAsciiText(const Table& catalog, const SearchResult& result,
                               const SearchSettings& settings);

}  // namespace octarc
