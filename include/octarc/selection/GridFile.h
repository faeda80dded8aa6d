// The occupation grid as a saved artefact (METHOD.md section 4): a FITS file, through
// io/FitsTable, reusable by every search on the same survey setup.
//
// Layout: an empty primary HDU and one BINTABLE, OCC_GRID. Its header holds OCTGRID (format
// version, 2), the axes (GRIDDIM; AXEXPRn, AXLOn, AXHIn, AXBINSn for n = 1..GRIDDIM), the axes
// asked for but dropped to keep the contour connected (NDROPAX; DROPAXn, in the order dropped),
// the contour (PLEVEL = P, PSELECT = what the selected bins hold, NSELECT), the counts (NBINNED,
// NOUTSIDE, NUNDEF, NOCCUP; WBINNED the binned weight), the search space (SPACE, SPACEEXP;
// empty for every simulated arc) and the survey setup (PIXSCALE, SEEING, GAIN, SKYSIGMA, NTHRESH
// and THRESHn in sigma, MINAREA, POPFILE, SEED, NSYSTEMS; NaN as an undefined value). One row
// per occupied bin, in probability order (rank = row - 1): BIN (the 0-based index along each
// axis), COUNT (samples), WEIGHT (their SIM_WEIGHT sum), PROB, CUMPROB (the contour level at
// which the bin enters) and SELECTED (1 in the contour at PLEVEL).
//
// Version 1 files (no WEIGHT column, no NDROPAX) are read with the counts as the weights.
#pragma once

#include <string>
#include <vector>

#include "octarc/selection/OccupationGrid.h"
#include "octarc/selection/SurveySetup.h"

namespace octarc {

struct GridProvenance {
  std::string searchSpace;            // name of the search space, "" for every simulated arc
  std::string searchSpaceExpression;  // its cut
  SurveySetup setup;
  std::vector<std::string> droppedAxes;  // asked for, not in the grid (in the order dropped)
};

struct SavedGrid {
  OccupationGrid grid;
  Contour contour;
  GridProvenance provenance;
};

// Writes the grid file at `path` itself (not atomically: give the temporary path of an
// AtomicFile / OutputFiles entry). Throws ConfigError when the contour is not the grid's contour
// at its level, IoError naming the file when it cannot be written.
void saveGrid(const std::string& path, const SavedGrid& saved);

// Reads a grid file. Throws IoError naming the file and what is wrong when it is not a grid
// (no OCC_GRID table, a missing keyword or column) or is inconsistent (bins outside the axes or
// given twice, counts that do not add up, an order or contour that is not the one the counts
// give).
SavedGrid loadGrid(const std::string& path);

}  // namespace octarc
