// The search (METHOD.md section 4): from a multi-threshold catalog of one image to lens
// candidates, in memory.
//
//   catalog rows (every level) --> searched area (selection/SearchMask.h, on X_IMAGE, Y_IMAGE)
//     --> selection: SNR_ISO > S/N floor, resolved (sqrt(2) SIZE_IMAGE > RESOLVED_MIN), then
//         GRID: in the grid's own search space, in a selected bin of the grid
//         (selection/GridScore.h); TREES: LENS_SCORE of the lens model at least SCORE_MIN
//         (selection/LensModel.h, with each row's context, selection/ArcContext.h)
//     --> LENS_SCORE of every selected row (below), the best row of each object the
//         highest-scoring one
//     --> one candidate per physical object (search/LevelMerge.h), ordered by LENS_SCORE
//     --> its lens and Einstein radius (search/LensFinder.h), its name (search/CandidateName.h):
//         the galaxies near the arc, and the arc's own object when its brightest peak lies off
//         its centroid (an arc blended with its lens), compared by their brightest peaks (the
//         highest level their object reaches, then FLUX_MAX when the catalog has it)
//     --> with colour bands: magnitudes of the arc and the lens (measure/Colour.h), the
//         dark-lens pair criterion (search/DarkLens.h), the colour cut
//
// LENS_SCORE reads as the expected fraction of lens arcs among rows of that score: the odds of
// an arc row against another row, times the prior odds, the prior being LENS_DENSITY arc systems
// per deg2 seen in ARCROWS rows each (the model's; 1 for GRID) among the rows above the S/N
// floor and resolved
// (selection/LensModel.h, searchPriorFraction). TREES: the model's odds. GRID: the ratio of the
// arcs' density in the row's bin (its occupation probability) to the searched rows' own density
// there (the bin's share of them, one row added to every bin), so that a bin the survey fills is
// worth less than one only arcs reach.
//
// The report spaces (e.g. the paper's "a > 0.15, e > 0.6, S/N > 40") only label candidates:
// a candidate is in a space when one of its passing rows is. Nothing here reads or writes files.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Table.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/io/Wcs.h"
#include "octarc/measure/Colour.h"
#include "octarc/search/DarkLens.h"
#include "octarc/search/LensFinder.h"
#include "octarc/selection/GridFile.h"
#include "octarc/selection/LensModel.h"
#include "octarc/selection/SearchMask.h"
#include "octarc/selection/SearchSpace.h"

namespace octarc {

// The catalog columns the search reads (besides the grid's axes and the spaces' cuts). The arc's
// octopole frame angle is 0.5 atan2(E2_IMAGE, E1_IMAGE) (core/Conventions.h).
const std::vector<std::string>& searchRequiredColumns();

// CANDIDATE_FLAGS bits.
enum CandidateFlag : int {
  kCandidateDarkLens = 1,       // no galaxy on the concave side within LENS_RADIUS
  kCandidateNoCurvature = 2,    // no circle could be fitted to the arc's pixels (centroid used)
  kCandidateNoWcs = 4,          // the image has no celestial WCS: no RA, Dec or name
  kCandidateSideUnknown = 8,    // |ARCNESS| below LENS_SIDE_ARCNESS: the lens on any side
  kCandidateLensLight = 16,     // found in the lens-light residual: its lens is the fitted galaxy
  kCandidateDarkLensPair = 32,  // a same-colour counter-image and no lens (search/DarkLens.h)
  kCandidateLensInArc = 64,     // the lens is the brightest peak of the arc's own object (blended)
};

// Candidates are removed when, in `band`, the arc's colour minus the lens's exceeds
// maxArcMinusLensMag (lensed sources are usually bluer than their early-type lens); those
// without a lens or a colour are kept.
struct ColourCut {
  std::string band;  // one of SearchSettings::colourBands
  double maxArcMinusLensMag = 0.0;
};

// SearchInput::lensLightOf values other than a lens row.
inline constexpr std::int64_t kNotLensLightRow = -1;  // a row of the image itself
inline constexpr std::int64_t kLensOnlyRow = -2;      // a fitted galaxy kept as a lens only

enum class SelectionMethod { Grid, Trees };

// The most report spaces a search has: a candidate's SPACES column holds one bit per space.
inline constexpr int kMaxReportSpaces = 30;

struct SearchSettings {
  SelectionMethod method = SelectionMethod::Grid;  // SELECTION_METHOD
  double lensDensityPerDeg2 = 1.0;                 // LENS_DENSITY: the prior of LENS_SCORE
  double scoreMin = 0.0;                           // SCORE_MIN: LENS_SCORE at least this
  int threads = 0;                                 // of the model's prediction (0: every core)
  double snrMin = 40.0;                            // S/N floor: SNR_ISO above it
  double resolvedMinArcsec = 1.0;  // resolved: sqrt(2) * SIZE_IMAGE above it (METHOD 3)
  double pixelScaleArcsec = 0.0;   // > 0
  double lensRadiusArcsec = 6.0;   // how far from the arc a lens may lie
  // Below this |ARCNESS| the arc's curvature, hence its concave side, is not measurable (noise
  // gives ordinary galaxies a median of about 0.01): the lens is the nearest galaxy on any side.
  double sideMinArcness = 0.05;
  std::vector<SearchSpace> reportSpaces;  // at most kMaxReportSpaces
  std::string namePrefix = "OCTARC";      // of the IAU-style designations
  // The colour bands' names, in the order of SearchInput::bands (none: no colours).
  std::vector<std::string> colourBands;
  std::optional<ColourCut> colourCut;
  ColourMatch pairColourMatch;  // same colour, for a dark-lens pair
  // The run's number of threshold levels: the length of the candidates' LEVELS vector (0: the
  // highest level a candidate passed).
  int levelCount = 0;
};

// The lens of a candidate, when one was found.
struct CandidateLens {
  std::size_t row = 0;            // in the catalog
  double xPix = 0.0, yPix = 0.0;  // 1-based
  double raDeg = std::numeric_limits<double>::quiet_NaN();
  double decDeg = std::numeric_limits<double>::quiet_NaN();
  // NaN when the arc lies on the lens; how it was estimated (search/LensFinder.h).
  double einsteinRadiusArcsec = std::numeric_limits<double>::quiet_NaN();
  ThetaEMethod thetaEMethod = ThetaEMethod::kNone;
  double distanceArcsec = 0.0;  // from the arc (the passing row farthest from it, when blended)
};

// A position of a candidate's other image.
struct CandidateImage {
  std::size_t row = 0;            // in the catalog
  double xPix = 0.0, yPix = 0.0;  // 1-based
  double raDeg = std::numeric_limits<double>::quiet_NaN();
  double decDeg = std::numeric_limits<double>::quiet_NaN();
};

struct Candidate {
  std::size_t row = 0;            // the best row, in the catalog
  std::vector<std::size_t> rows;  // every passing row of the object
  std::vector<int> passedLevels;
  std::uint32_t spaces = 0;   // bit i: in report space i
  double lensScore = 0.0;     // LENS_SCORE of the best row
  double probability = 0.0;   // of the best row's grid bin (NaN with TREES)
  double contourLevel = 0.0;  // at which that bin enters the contour (NaN with TREES)
  std::string name;           // designation, "" without WCS
  double raDeg = std::numeric_limits<double>::quiet_NaN();  // J2000 of the best row
  double decDeg = std::numeric_limits<double>::quiet_NaN();
  std::optional<CircleFit> curvature;  // in 1-based pixel coordinates
  std::optional<CandidateLens> lens;
  int flags = 0;  // CandidateFlag bits
  // With colour bands: isophotal magnitudes in the footprints of the best row and of the lens
  // row, [0] in the measurement band, [1 + b] in colour band b (lensMags empty without a lens).
  std::vector<BandMagnitude> arcMags, lensMags;
  std::optional<CandidateImage> secondary;  // the counter-image of a kCandidateDarkLensPair
};

struct SpaceCount {
  std::string name;
  std::string expression;
  std::int64_t candidates = 0;
  std::int64_t rowsPassed = 0;  // selected rows inside the space
};

struct SearchSummary {
  std::int64_t rowsSearched = 0;     // catalog rows (every level) inside the searched area
  std::int64_t objectsSearched = 0;  // level-1 objects inside it
  std::int64_t rowsSelected = 0;     // rows that passed every cut
  std::int64_t candidates = 0;
  std::int64_t removedByColourCut = 0;  // not among `candidates`
  // From the WCS, pixel block by block; without one, from the pixel scale.
  double searchedAreaDeg2 = std::numeric_limits<double>::quiet_NaN();
  std::int64_t searchedPixels = 0;
  std::vector<SpaceCount> spaces;  // the report spaces, in order
  std::int64_t rowsScored = 0;     // rows above the S/N floor and resolved (the prior's rows)
  double priorFraction = 0.0;      // the prior of LENS_SCORE (searchPriorFraction)
  // Candidates per square degree (NaN without area) and the fraction of searched rows rejected.
  double candidatesPerDeg2() const;
  double rejectedFraction() const;
};

struct SearchResult {
  std::vector<Candidate> candidates;  // by LENS_SCORE, highest first (LENS_RANK 1 first)
  SearchSummary summary;
};

// What the search reads. `footprints` and `pixels` (the background-subtracted measurement image)
// give the arcs' pixels for the curvature fit; without them the lens is looked for from the arc
// centroid (kCandidateNoCurvature). `bands` (one per SearchSettings::colourBands, on the pixel grid
// of the footprints, which they need) and `measurementBand` (the measurement image, unsubtracted
// also when `pixels` is a lens-light residual) give colours.
struct SearchInput {
  const Table* catalog = nullptr;   // every level, searchRequiredColumns() and the grid's columns
  const SavedGrid* grid = nullptr;  // SELECTION_METHOD GRID
  const SearchMask* mask = nullptr;
  const Wcs* wcs = nullptr;  // null: pixel positions only
  const SegmentationRuns* footprints = nullptr;
  const ImageF* pixels = nullptr;
  // Lens-light subtraction (search/LensLightSearch.h); empty: none. Per catalog row: the row of
  // the fitted galaxy that is its lens when the row was measured on the residual, else
  // kNotLensLightRow, or kLensOnlyRow for a galaxy's own row that is never selected. Residual
  // rows' curvature is fitted on `residualPixels`.
  const std::vector<std::int64_t>* lensLightOf = nullptr;
  const ImageF* residualPixels = nullptr;
  // Per fitted galaxy's catalog row, its fitted centre (1-based pixels): the lens position of
  // the arcs found in its residual, not pulled towards them as its catalog centroid is (the
  // arc is part of the galaxy's object). Null or a row not in it: the catalog's centroid.
  const std::map<std::size_t, std::pair<double, double>>* fittedCentres = nullptr;
  // LENS_LIGHT LOCAL: the residual's rows add to the image's, so a residual candidate within
  // 1" of one of the image's is the same object, and is dropped; the image's candidates look
  // for lenses and counter-images among the image's rows only, and objectsSearched counts
  // the image's objects.
  bool residualRowsAreExtra = false;
  const BandImage* measurementBand = nullptr;
  const std::vector<BandImage>* bands = nullptr;
  // SELECTION_METHOD TREES: the lens model (the catalog then needs FLUX_ISO, ARCNESS,
  // ANTIARCNESS and E_IMAGE too).
  const SavedLensModel* model = nullptr;
};

// ConfigError for a missing column, a bad setting or inconsistent inputs.
SearchResult searchCandidates(const SearchInput& input, const SearchSettings& settings);

}  // namespace octarc
