#include "octarc/search/Search.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/search/CandidateName.h"
#include "octarc/search/LevelMerge.h"
#include "octarc/selection/GridScore.h"

namespace octarc {

namespace {

// The brightest peak of an arc's own object at least this far from its centroid is a lens it is
// blended with: nearer, it is the arc's own core (a curved arc's centroid lies inside its ridge
// by less than this at the scales of ground surveys; measured on injected lenses, README).
constexpr double kInArcPeakMinArcsec = 0.2;

// The catalog columns the search reads, by index.
struct SearchColumns {
  int x, y, level, number, parent, snr, size, e1, e2, arcSide;
  explicit SearchColumns(const Table& t)
      : x(t.requireColumn("X_IMAGE", "search")),
        y(t.requireColumn("Y_IMAGE", "search")),
        level(t.requireColumn("THRESH_LEVEL", "search")),
        number(t.requireColumn("NUMBER", "search")),
        parent(t.requireColumn("PARENT_NUMBER", "search")),
        snr(t.requireColumn("SNR_ISO", "search")),
        size(t.requireColumn("SIZE_IMAGE", "search")),
        e1(t.requireColumn("E1_IMAGE", "search")),
        e2(t.requireColumn("E2_IMAGE", "search")),
        arcSide(t.requireColumn("ARC_SIDE", "search")) {}
};

bool wholeIn(double v, double lo, double hi) {
  return v >= lo && v <= hi && v == std::floor(v);
}

std::int64_t treeKey(int level, std::int32_t number) {
  return (std::int64_t(level) << 32) | std::uint32_t(number);
}

// The rows of each level in square cells of a given side, to find the galaxies near an arc
// without a pass over the whole catalog per candidate.
class RowCells {
 public:
  RowCells(const Table& catalog, const SearchColumns& c, const std::vector<TreeRow>& tree,
           double cellPix)
      : cellPix_(std::max(cellPix, 1.0)) {
    for (std::size_t i = 0; i < tree.size(); ++i) {
      const double x = catalog.value(std::int64_t(i), c.x);
      const double y = catalog.value(std::int64_t(i), c.y);
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      cells_[key(tree[i].level, cell(x), cell(y))].push_back(i);
    }
  }
  // Calls f(row) for the rows of `level` in the 3 x 3 cells around (x, y): every row within one
  // cell side, and some beyond.
  template <typename F>
  void forEachNear(int level, double x, double y, F&& f) const {
    const std::int64_t cx = cell(x), cy = cell(y);
    for (std::int64_t j = cy - 1; j <= cy + 1; ++j) {
      for (std::int64_t i = cx - 1; i <= cx + 1; ++i) {
        const auto found = cells_.find(key(level, i, j));
        if (found == cells_.end()) continue;
        for (const std::size_t row : found->second) f(row);
      }
    }
  }

 private:
  std::int64_t cell(double v) const { return std::int64_t(std::floor(v / cellPix_)); }
  static std::int64_t key(int level, std::int64_t i, std::int64_t j) {
    // Cells of at least one pixel: indices fit in 24 bits for images up to 16 million pixels
    // on a side (positions slightly outside the image give small negative indices).
    return (std::int64_t(level) << 48) | ((i & 0xffffff) << 24) | (j & 0xffffff);
  }
  double cellPix_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

// The circle fitted to an arc's pixels (1-based coordinates) weighted by their flux.
std::optional<CircleFit> curvatureOf(const ImageF& pixels, const std::vector<PixelRun>& runs) {
  std::vector<double> xs, ys, ws;
  for (const PixelRun& run : runs) {
    for (std::int32_t x = run.x0; x <= run.x1; ++x) {
      xs.push_back(toFitsPixel(x));
      ys.push_back(toFitsPixel(run.y));
      ws.push_back(pixels(x, run.y));
    }
  }
  return fitCircle(xs, ys, ws);
}

// The lens-light origin of row i (SearchInput::lensLightOf).
std::int64_t lensLightOf(const SearchInput& in, std::size_t i) {
  return in.lensLightOf != nullptr ? (*in.lensLightOf)[i] : kNotLensLightRow;
}

// LENS_LIGHT LOCAL: row i is the residual's, added to the image's rows (an object of the image
// seen again, or a lens's remains), so never an image arc's lens or counter-image, nor an object
// counted again.
bool addedResidualRow(const SearchInput& in, std::size_t i) {
  return in.residualRowsAreExtra && lensLightOf(in, i) >= 0;
}

// The circle fits of the objects' best rows, every level's footprints gathered in one pass; a
// row measured on the lens-light residual is fitted on the residual's pixels.
std::vector<std::optional<CircleFit>> curvaturesOf(const SearchInput& in,
                                                   const std::vector<MergedObject>& objects,
                                                   const std::vector<TreeRow>& tree) {
  std::vector<std::optional<CircleFit>> out(objects.size());
  if (in.footprints == nullptr || in.pixels == nullptr) return out;
  std::map<int, std::vector<std::size_t>> byLevel;  // level -> objects
  for (std::size_t k = 0; k < objects.size(); ++k) {
    byLevel[tree[objects[k].bestRow].level].push_back(k);
  }
  for (const auto& [level, members] : byLevel) {
    std::vector<std::int32_t> numbers;
    for (const std::size_t k : members) numbers.push_back(tree[objects[k].bestRow].number);
    const std::vector<std::vector<PixelRun>> runs = in.footprints->footprints(level, numbers);
    for (std::size_t i = 0; i < members.size(); ++i) {
      const bool residual =
          in.residualPixels != nullptr && lensLightOf(in, objects[members[i]].bestRow) >= 0;
      out[members[i]] = curvatureOf(residual ? *in.residualPixels : *in.pixels, runs[i]);
    }
  }
  return out;
}

// LENS_LIGHT LOCAL: an object that separates in the image itself is found in the residual too.
// The image's candidate stays (the residual only adds), the residual's copy within
// kSameArcArcsec of it goes.
void dropResidualDuplicates(const Table& catalog, const SearchColumns& c, const SearchSettings& s,
                            std::vector<Candidate>& candidates) {
  constexpr double kSameArcArcsec = 1.0;
  const double samePix = kSameArcArcsec / s.pixelScaleArcsec;
  auto position = [&](const Candidate& cand) {
    return std::pair{catalog.value(std::int64_t(cand.row), c.x),
                     catalog.value(std::int64_t(cand.row), c.y)};
  };
  auto isTwin = [&](const Candidate& cand) {
    if (!(cand.flags & kCandidateLensLight)) return false;
    // Plain variables, not a structured binding: clang 14 cannot capture one in a lambda.
    const std::pair<double, double> xy = position(cand);
    return std::any_of(candidates.begin(), candidates.end(), [&](const Candidate& o) {
      if (o.flags & kCandidateLensLight) return false;
      const std::pair<double, double> oxy = position(o);
      return std::hypot(oxy.first - xy.first, oxy.second - xy.second) < samePix;
    });
  };
  std::vector<bool> twin(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) twin[i] = isTwin(candidates[i]);
  std::vector<Candidate> kept;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!twin[i]) kept.push_back(std::move(candidates[i]));
  }
  candidates = std::move(kept);
}

// The parent links of the catalog, to tell the rows of one object at several levels.
struct RowIndex {
  const std::vector<TreeRow>& tree;
  const std::unordered_map<std::int64_t, std::size_t>& rowOf;

  // The row of `row`'s object at `level` (<= its own level), if every link down there exists.
  std::optional<std::size_t> ancestorAt(std::size_t row, int level) const {
    while (tree[row].level > level) {
      const auto up = rowOf.find(treeKey(tree[row].level - 1, tree[row].parentNumber));
      if (up == rowOf.end()) return std::nullopt;
      row = up->second;
    }
    return tree[row].level == level ? std::optional<std::size_t>(row) : std::nullopt;
  }
  // True when one row's footprint holds the other's: one object seen at two levels.
  bool related(std::size_t a, std::size_t b) const {
    if (tree[a].level < tree[b].level) std::swap(a, b);
    return ancestorAt(a, tree[b].level) == b;
  }
};

// The brightest peak of each row's object: the row at the highest level among the row and its
// descendants, the brighter FLUX_MAX (when known) between rows of one level, then the lower row.
std::vector<std::size_t> brightestPeaks(const std::vector<TreeRow>& tree,
                                        const std::unordered_map<std::int64_t, std::size_t>& rowOf,
                                        const std::vector<double>& fluxMax) {
  std::vector<std::size_t> peak(tree.size());
  std::vector<std::size_t> order(tree.size());
  for (std::size_t i = 0; i < tree.size(); ++i) peak[i] = order[i] = i;
  auto brighter = [&](std::size_t a, std::size_t b) {
    if (tree[a].level != tree[b].level) return tree[a].level > tree[b].level;
    const double fa = fluxMax.empty() ? kNaN : fluxMax[a];
    const double fb = fluxMax.empty() ? kNaN : fluxMax[b];
    if (fa > fb || (!std::isnan(fa) && std::isnan(fb))) return true;
    if (fb > fa || (!std::isnan(fb) && std::isnan(fa))) return false;
    return a < b;
  };
  // Children before parents: each passes its peak down one level.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return tree[a].level > tree[b].level; });
  for (const std::size_t i : order) {
    if (tree[i].level <= 1) continue;
    const auto up = rowOf.find(treeKey(tree[i].level - 1, tree[i].parentNumber));
    if (up == rowOf.end()) continue;
    if (brighter(peak[i], peak[up->second])) peak[up->second] = peak[i];
  }
  return peak;
}

// Where a candidate's counter-image may be: the rows placed as one, and the other objects near
// the centre of curvature (which would be a visible lens).
struct PairSearch {
  std::vector<std::size_t> counterImages;
  std::vector<LensCandidateGalaxy> nearCentre;
};

// The magnitudes of `rows` in the measurement band and each colour band, in the footprints of
// those rows: one pass over each level's footprints.
std::unordered_map<std::size_t, std::vector<BandMagnitude>> bandMagnitudes(
    const SearchInput& in, const std::vector<TreeRow>& tree, const std::set<std::size_t>& rows) {
  std::map<int, std::vector<std::size_t>> byLevel;
  for (const std::size_t r : rows) byLevel[tree[r].level].push_back(r);
  std::unordered_map<std::size_t, std::vector<BandMagnitude>> out;
  for (const auto& [level, members] : byLevel) {
    std::vector<std::int32_t> numbers;
    for (const std::size_t r : members) numbers.push_back(tree[r].number);
    const std::vector<std::vector<PixelRun>> runs = in.footprints->footprints(level, numbers);
    for (std::size_t i = 0; i < members.size(); ++i) {
      std::vector<BandMagnitude>& mags = out[members[i]];
      mags.push_back(isoMagnitude(*in.measurementBand, runs[i]));
      for (const BandImage& band : *in.bands) mags.push_back(isoMagnitude(band, runs[i]));
    }
  }
  return out;
}

// True when every band's colour of `a` matches that of `b`.
bool sameColours(const std::vector<BandMagnitude>& a, const std::vector<BandMagnitude>& b,
                 const ColourMatch& match) {
  for (std::size_t k = 1; k < a.size(); ++k) {
    if (!sameColour(colourOf(a[k], a[0]), colourOf(b[k], b[0]), match)) return false;
  }
  return a.size() > 1;
}

// The arc's and the lens's magnitudes in every band, and the dark-lens pair criterion
// (search/DarkLens.h): the counter-image is looked for from the arc's level down to level 1,
// the most opposite one of the first level that has one of the arc's colour; the centre must
// hold no object but the arc's and the counter-image's rows at level 1 and the arc's level.
void addColours(const SearchInput& in, const SearchSettings& s, const SearchColumns& c,
                const RowIndex& index, const RowCells& nearby, double lensRadiusPix,
                std::vector<Candidate>& candidates) {
  const Table& catalog = *in.catalog;
  auto xOf = [&](std::size_t r) { return catalog.value(std::int64_t(r), c.x); };
  auto yOf = [&](std::size_t r) { return catalog.value(std::int64_t(r), c.y); };
  std::vector<PairSearch> pairs(candidates.size());
  std::set<std::size_t> measured;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const Candidate& cand = candidates[k];
    measured.insert(cand.row);
    if (cand.lens) measured.insert(cand.lens->row);
    // Without a measurable concave side, or for a nearly straight arc, no centre to look from;
    // an arc found in a fitted galaxy's residual has that galaxy as its lens.
    if (!cand.curvature || (cand.flags & (kCandidateSideUnknown | kCandidateLensLight)) ||
        !(cand.curvature->radius <= lensRadiusPix)) {
      continue;
    }
    const CircleFit& circle = *cand.curvature;
    const int arcLevel = index.tree[cand.row].level;
    for (int level = 1; level <= arcLevel; ++level) {
      nearby.forEachNear(level, circle.xCentre, circle.yCentre, [&](std::size_t i) {
        if (index.related(i, cand.row)) return;
        if (addedResidualRow(in, i)) return;
        if (counterImagePlace(circle, xOf(cand.row), yOf(cand.row), xOf(i), yOf(i))) {
          pairs[k].counterImages.push_back(i);
          measured.insert(i);
        }
        if (level == 1 || level == arcLevel) pairs[k].nearCentre.push_back({xOf(i), yOf(i), i});
      });
    }
  }
  const auto mags = bandMagnitudes(in, index.tree, measured);

  for (std::size_t k = 0; k < candidates.size(); ++k) {
    Candidate& cand = candidates[k];
    cand.arcMags = mags.at(cand.row);
    if (cand.lens) cand.lensMags = mags.at(cand.lens->row);
    if (pairs[k].counterImages.empty()) continue;
    const CircleFit& circle = *cand.curvature;
    // Highest level first, then the most opposite (smallest cosine of the angle at C).
    auto cosAngle = [&](std::size_t r) {
      const double ax = xOf(cand.row) - circle.xCentre, ay = yOf(cand.row) - circle.yCentre;
      const double sx = xOf(r) - circle.xCentre, sy = yOf(r) - circle.yCentre;
      return (ax * sx + ay * sy) / (std::hypot(ax, ay) * std::hypot(sx, sy));
    };
    std::vector<std::size_t>& order = pairs[k].counterImages;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      if (index.tree[a].level != index.tree[b].level) {
        return index.tree[a].level > index.tree[b].level;
      }
      return cosAngle(a) < cosAngle(b);
    });
    const auto found = std::find_if(order.begin(), order.end(), [&](std::size_t r) {
      return sameColours(cand.arcMags, mags.at(r), s.pairColourMatch);
    });
    if (found == order.end()) continue;
    std::vector<LensCandidateGalaxy> others;
    for (const LensCandidateGalaxy& g : pairs[k].nearCentre) {
      if (!index.related(g.row, *found)) others.push_back(g);
    }
    if (!lensFreeCentre(circle, others)) continue;
    // The counter-image is not the lens findBrightestLens may have taken it for.
    cand.lens.reset();
    cand.lensMags.clear();
    cand.flags |= kCandidateDarkLens | kCandidateDarkLensPair;
    CandidateImage image;
    image.row = *found;
    image.xPix = xOf(*found);
    image.yPix = yOf(*found);
    if (in.wcs != nullptr) {
      const auto sky = in.wcs->pixelToJ2000(image.xPix, image.yPix);
      image.raDeg = sky[0];
      image.decDeg = sky[1];
    }
    cand.secondary = image;
  }
}

// True when the colour cut removes the candidate (see ColourCut).
bool failsColourCut(const Candidate& cand, std::size_t magIndex, double maxArcMinusLensMag) {
  if (cand.arcMags.size() <= magIndex || cand.lensMags.size() <= magIndex) return false;
  const Colour arc = colourOf(cand.arcMags[magIndex], cand.arcMags[0]);
  const Colour lens = colourOf(cand.lensMags[magIndex], cand.lensMags[0]);
  return arc.value - lens.value > maxArcMinusLensMag;  // false when either is NaN
}

}  // namespace

const std::vector<std::string>& searchRequiredColumns() {
  static const std::vector<std::string> columns = {
      "X_IMAGE", "Y_IMAGE",    "THRESH_LEVEL", "NUMBER",   "PARENT_NUMBER",
      "SNR_ISO", "SIZE_IMAGE", "E1_IMAGE",     "E2_IMAGE", "ARC_SIDE"};
  return columns;
}

double SearchSummary::candidatesPerDeg2() const {
  return searchedAreaDeg2 > 0.0 ? double(candidates) / searchedAreaDeg2 : kNaN;
}

double SearchSummary::rejectedFraction() const {
  return rowsSearched > 0 ? 1.0 - double(rowsSelected) / double(rowsSearched) : kNaN;
}

namespace {

// ConfigError for inputs and settings a search cannot run with.
void checkSearchInput(const SearchInput& in, const SearchSettings& s) {
  const bool trees = s.method == SelectionMethod::Trees;
  if (in.catalog == nullptr || in.mask == nullptr ||
      (trees ? in.model == nullptr : in.grid == nullptr)) {
    throw ConfigError(trees ? "search: a catalog, a lens model and a searched area are needed"
                            : "search: a catalog, a grid and a searched area are needed");
  }
  if (!(s.pixelScaleArcsec > 0.0)) throw ConfigError("search: the pixel scale must be positive");
  if (!(s.lensRadiusArcsec >= 0.0)) throw ConfigError("LENS_RADIUS: must not be negative");
  if (!(s.lensDensityPerDeg2 > 0.0)) throw ConfigError("LENS_DENSITY: must be positive");
  if (s.reportSpaces.size() > std::size_t(kMaxReportSpaces)) {
    throw ConfigError("SEARCH_SPACE: at most " + std::to_string(kMaxReportSpaces) + " spaces");
  }
  if (!s.colourBands.empty() && (in.bands == nullptr || in.bands->size() != s.colourBands.size() ||
                                 in.measurementBand == nullptr || in.footprints == nullptr)) {
    throw ConfigError("search: colours need the footprints and one image per colour band");
  }
  if (s.colourCut && std::find(s.colourBands.begin(), s.colourBands.end(), s.colourCut->band) ==
                         s.colourBands.end()) {
    throw ConfigError("COLOUR_CUT: band " + s.colourCut->band + " is not one of COLOUR_BAND");
  }
}

// The catalog's component tree and the rows scored: inside the searched area, above the S/N
// floor and resolved. Counts the rows and objects searched.
struct ScoredRows {
  std::vector<TreeRow> tree;
  std::unordered_map<std::int64_t, std::size_t> rowOf;
  std::vector<std::int64_t> scored;
};

ScoredRows selectScoredRows(const SearchInput& in, const SearchSettings& s, const SearchColumns& c,
                            SearchSummary& summary) {
  const Table& catalog = *in.catalog;
  const std::int64_t n = catalog.rows();
  ScoredRows out;
  std::vector<TreeRow>& tree = out.tree;
  std::unordered_map<std::int64_t, std::size_t>& rowOf = out.rowOf;
  std::vector<std::int64_t>& scored = out.scored;
  tree.resize(static_cast<std::size_t>(n));
  rowOf.reserve(std::size_t(n));
  const double resolvedMinPix = s.resolvedMinArcsec / s.pixelScaleArcsec;
  for (std::int64_t r = 0; r < n; ++r) {
    const std::size_t i = std::size_t(r);
    const double level = catalog.value(r, c.level), number = catalog.value(r, c.number);
    const double parent = catalog.value(r, c.parent);
    if (!wholeIn(level, 1, 255) || !wholeIn(number, 1, 2147483647.0) ||
        !wholeIn(parent, 0, 2147483647.0)) {
      throw ConfigError("search: catalog row " + std::to_string(r + 1) +
                        ": THRESH_LEVEL, NUMBER or PARENT_NUMBER is not a level 1-255 and "
                        "object numbers of a multi-threshold run");
    }
    tree[i] = {int(level), std::int32_t(number), std::int32_t(parent)};
    rowOf[treeKey(tree[i].level, tree[i].number)] = i;
    if (lensLightOf(in, i) == kLensOnlyRow) continue;  // a fitted galaxy: a lens, never an arc
    if (!in.mask->searched(catalog.value(r, c.x), catalog.value(r, c.y))) continue;
    ++summary.rowsSearched;
    if (tree[i].level == 1 && !addedResidualRow(in, i)) ++summary.objectsSearched;
    const double snr = catalog.value(r, c.snr);
    const double size = catalog.value(r, c.size);
    if (snr > s.snrMin && std::sqrt(2.0) * size > resolvedMinPix) scored.push_back(r);
  }
  return out;
}

// LENS_SCORE of the rows scored (NaN for the others): the trees' odds, or the grid's
// probability of the row's bin against the searched rows' share of it, with the prior.
std::vector<double> lensScores(const SearchInput& in, const SearchSettings& s,
                               const std::vector<std::int64_t>& scored,
                               const std::vector<RowScore>& scores, const SearchSummary& summary) {
  const Table& catalog = *in.catalog;
  const bool trees = s.method == SelectionMethod::Trees;
  const double priorLogOdds = std::log(summary.priorFraction / (1.0 - summary.priorFraction));
  std::vector<double> lensScore(std::size_t(catalog.rows()), kNaN);
  if (trees) {
    const std::vector<ArcContext> contexts =
        arcContexts(catalog, {s.pixelScaleArcsec, in.model->contextRadiusArcsec});
    const FeatureRows features = lensFeatures(catalog, scored, s.pixelScaleArcsec, &contexts);
    const std::vector<double> logOdds = in.model->trees.logOdds(features, s.threads);
    const double shift = priorLogOddsShift(in.model->training, summary.priorFraction);
    for (std::size_t k = 0; k < scored.size(); ++k) {
      lensScore[std::size_t(scored[k])] = logistic(logOdds[k] + shift);
    }
  } else {
    // The searched rows' share of each occupied bin, one row added to every bin.
    std::vector<double> rowsInBin(std::size_t(in.grid->grid.occupiedBins()), 1.0);
    for (const std::int64_t r : scored) {
      if (scores[std::size_t(r)].rank >= 0)
        rowsInBin[std::size_t(scores[std::size_t(r)].rank)] += 1;
    }
    const double rowsTotal = double(scored.size()) + double(rowsInBin.size());
    for (const std::int64_t r : scored) {
      const RowScore& score = scores[std::size_t(r)];
      if (score.rank < 0) continue;
      const double rowShare = rowsInBin[std::size_t(score.rank)] / rowsTotal;
      lensScore[std::size_t(r)] = logistic(std::log(score.probability / rowShare) + priorLogOdds);
    }
  }
  return lensScore;
}

// The grid's scores of every row and its own search space (GRID).
struct GridScores {
  std::vector<RowScore> scores;
  std::vector<bool> inSpace;
};

GridScores gridScores(const SavedGrid& grid, const Table& catalog) {
  GridScores out{scoreRows(grid.grid, grid.contour, catalog),
                 std::vector<bool>(std::size_t(catalog.rows()), true)};
  if (!grid.provenance.searchSpaceExpression.empty()) {
    out.inSpace = SearchSpace(grid.provenance.searchSpace.empty() ? std::string("grid")
                                                                  : grid.provenance.searchSpace,
                              grid.provenance.searchSpaceExpression)
                      .mask(catalog);
  }
  return out;
}

// The scored rows that pass: LENS_SCORE at least SCORE_MIN and, with the grid, in its contour
// and search space. Counts them, overall and per report space.
std::vector<bool> passedRows(const SearchSettings& s, const std::vector<std::int64_t>& scored,
                             const std::vector<double>& lensScore, const GridScores& grid,
                             const std::vector<std::vector<bool>>& spaceMasks, std::size_t rows,
                             SearchSummary& summary) {
  const bool trees = s.method == SelectionMethod::Trees;
  std::vector<bool> passed(rows, false);
  for (const std::int64_t r : scored) {
    const std::size_t i = std::size_t(r);
    passed[i] =
        lensScore[i] >= s.scoreMin && (trees || (grid.inSpace[i] && grid.scores[i].selected));
    if (passed[i]) ++summary.rowsSelected;
  }
  for (std::size_t k = 0; k < s.reportSpaces.size(); ++k) {
    SpaceCount count{s.reportSpaces[k].name(), s.reportSpaces[k].expression(), 0, 0};
    for (std::size_t i = 0; i < passed.size(); ++i)
      count.rowsPassed += passed[i] && spaceMasks[k][i];
    summary.spaces.push_back(count);
  }
  return passed;
}

// A column's values, or none when the catalog lacks it.
std::vector<double> columnValues(const Table& catalog, const char* name) {
  const int column = catalog.findColumn(name);
  std::vector<double> values;
  if (column < 0) return values;
  for (std::int64_t r = 0; r < catalog.rows(); ++r) values.push_back(catalog.value(r, column));
  return values;
}

// The candidates, overall and per report space.
void countCandidates(const SearchSettings& s, SearchResult& result) {
  for (const Candidate& cand : result.candidates) {
    for (std::size_t k = 0; k < s.reportSpaces.size(); ++k) {
      if (cand.spaces & (1u << k)) ++result.summary.spaces[k].candidates;
    }
  }
  result.summary.candidates = std::int64_t(result.candidates.size());
}

// What every candidate is made from: the catalog, its component tree, the rows near each
// position, each row's brightest peak, the scores.
struct CandidateContext {
  const SearchInput& in;
  const SearchSettings& s;
  const Table& catalog;
  const SearchColumns& c;
  const std::vector<TreeRow>& tree;
  const std::unordered_map<std::int64_t, std::size_t>& rowOf;
  const RowCells& nearby;
  const RowIndex& index;
  const std::vector<std::size_t>& peaks;
  const std::vector<double>& fluxMax;
  const std::vector<double>& lensScore;
  const std::vector<RowScore>& scores;
  const std::vector<std::vector<bool>>& spaceMasks;
  int arcnessColumn = -1;
  int maxLevel = 1;
  double lensRadiusPix = 0.0;
  double inArcPeakMinPix = 0.0;  // a blend's peak nearer its centroid is the arc's own core
  double x(std::size_t r) const { return catalog.value(std::int64_t(r), c.x); }
  double y(std::size_t r) const { return catalog.value(std::int64_t(r), c.y); }
};

// The galaxies that may be the lens of `object` (best row at x, y): another galaxy at the arc's
// level or at the lowest one; the arc's own ancestors contain it (their centroids are pulled
// towards it) and are left out. Each is placed at, and compared by, its brightest peak.
std::vector<LensCandidateGalaxy> lensGalaxies(const CandidateContext& k, const MergedObject& object,
                                              double x, double y) {
  const SearchInput& in = k.in;
  const TreeRow& id = k.tree[object.bestRow];
  std::vector<std::size_t> ancestors;
  for (TreeRow walk = id; walk.level > 1;) {
    const auto up = k.rowOf.find(treeKey(walk.level - 1, walk.parentNumber));
    if (up == k.rowOf.end()) break;
    ancestors.push_back(up->second);
    walk = k.tree[up->second];
  }
  const bool imageArc = lensLightOf(in, object.bestRow) < 0;
  auto galaxyAt = [&](std::size_t row, bool inArc) {
    const std::size_t p = k.peaks[row];
    return LensCandidateGalaxy{
        k.x(p), k.y(p), row, k.tree[p].level, k.fluxMax.empty() ? kNaN : k.fluxMax[p], inArc};
  };
  std::vector<LensCandidateGalaxy> galaxies;
  for (const int level : {1, id.level}) {
    k.nearby.forEachNear(level, x, y, [&](std::size_t i) {
      if (i == object.bestRow ||
          std::find(ancestors.begin(), ancestors.end(), i) != ancestors.end() ||
          (imageArc && addedResidualRow(in, i))) {
        return;
      }
      if (std::hypot(k.x(i) - x, k.y(i) - y) <= k.lensRadiusPix) {
        galaxies.push_back(galaxyAt(i, false));
      }
    });
    if (id.level == 1) break;
  }
  // An arc blended with its lens: the blend's brightest peak, off its centroid, is the lens's
  // core (a peak at the centroid is the arc's own).
  const std::size_t ownPeak = k.peaks[object.bestRow];
  if (imageArc && std::hypot(k.x(ownPeak) - x, k.y(ownPeak) - y) >= k.inArcPeakMinPix) {
    galaxies.push_back(galaxyAt(object.bestRow, true));
    galaxies.back().row = ownPeak;
  }
  return galaxies;
}

// The lens `match` names, its distance to the arc and the Einstein radius they give.
CandidateLens describeLens(const CandidateContext& k, const MergedObject& object,
                           const Candidate& cand, const LensMatch& match,
                           std::pair<double, double> lensXY, const ArcGeometry& arc) {
  const SearchInput& in = k.in;
  const double x = arc.xCentroid, y = arc.yCentroid;
  const std::int64_t fittedLens = lensLightOf(in, object.bestRow);
  const bool imageArc = fittedLens < 0;
  CandidateLens lens;
  lens.row = match.row;
  std::tie(lens.xPix, lens.yPix) = lensXY;
  if (in.wcs != nullptr) {
    const auto sky = in.wcs->pixelToJ2000(lens.xPix, lens.yPix);
    lens.raDeg = sky[0];
    lens.decDeg = sky[1];
  }
  // The arc's position: its centroid, or for a blend the passing row farthest from the lens
  // (the blend's centroid is pulled onto the lens).
  double xArc = x, yArc = y;
  std::vector<LensCandidateGalaxy> counterImages;
  if (cand.flags & kCandidateLensInArc) {
    for (const std::size_t r : object.rows) {
      if (std::hypot(k.x(r) - lens.xPix, k.y(r) - lens.yPix) >
          std::hypot(xArc - lens.xPix, yArc - lens.yPix)) {
        xArc = k.x(r);
        yArc = k.y(r);
      }
    }
  } else {
    // Possible counter-images: objects at any level near the lens, neither the arc's nor
    // the lens's core (a counter-image blended with the lens separates at a higher level).
    const std::size_t lensPeak = fittedLens >= 0 ? match.row : k.peaks[match.row];
    for (int level = 1; level <= k.maxLevel; ++level) {
      k.nearby.forEachNear(level, lens.xPix, lens.yPix, [&](std::size_t i) {
        if (k.index.related(i, object.bestRow) || k.index.related(i, lensPeak) ||
            std::size_t(fittedLens) == i || (imageArc && addedResidualRow(in, i)) ||
            lensLightOf(in, i) == kLensOnlyRow) {
          return;
        }
        counterImages.push_back({k.x(i), k.y(i), i});
      });
    }
  }
  const EinsteinRadiusEstimate estimate = estimateEinsteinRadius(
      lens.xPix, lens.yPix, xArc, yArc,
      (cand.flags & kCandidateLensInArc) ? std::nullopt : arc.curvature, counterImages);
  lens.distanceArcsec = std::hypot(xArc - lens.xPix, yArc - lens.yPix) * k.s.pixelScaleArcsec;
  lens.einsteinRadiusArcsec = estimate.thetaEPix * k.s.pixelScaleArcsec;
  lens.thetaEMethod = estimate.method;
  return lens;
}

// One object's candidate: its best row, scores, report spaces and position, its arc geometry,
// and its lens (or none: a possible dark lens).
Candidate makeCandidate(const CandidateContext& k, const MergedObject& object,
                        const std::optional<CircleFit>& curvature) {
  const SearchInput& in = k.in;
  const SearchSettings& s = k.s;
  const Table& catalog = k.catalog;
  const SearchColumns& c = k.c;
  const bool trees = s.method == SelectionMethod::Trees;
  Candidate cand;
  cand.row = object.bestRow;
  cand.rows = object.rows;
  cand.passedLevels = object.passedLevels;
  cand.lensScore = k.lensScore[object.bestRow];
  cand.probability = trees ? kNaN : k.scores[object.bestRow].probability;
  cand.contourLevel = trees ? kNaN : k.scores[object.bestRow].entryLevel;
  for (std::size_t space = 0; space < s.reportSpaces.size(); ++space) {
    for (const std::size_t r : object.rows) {
      if (k.spaceMasks[space][r]) cand.spaces |= 1u << space;
    }
  }
  const std::int64_t best = std::int64_t(object.bestRow);
  const double x = catalog.value(best, c.x);
  const double y = catalog.value(best, c.y);
  if (in.wcs != nullptr) {
    const auto sky = in.wcs->pixelToJ2000(x, y);
    cand.raDeg = sky[0];
    cand.decDeg = sky[1];
    cand.name = iauDesignation(s.namePrefix, sky[0], sky[1]);
  } else {
    cand.flags |= kCandidateNoWcs;
  }
  const std::vector<LensCandidateGalaxy> galaxies = lensGalaxies(k, object, x, y);
  ArcGeometry arc;
  arc.xCentroid = x;
  arc.yCentroid = y;
  arc.thetaRad = 0.5 * std::atan2(catalog.value(best, c.e2), catalog.value(best, c.e1));
  const double side = catalog.value(best, c.arcSide);
  arc.arcSide = side > 0 ? 1 : side < 0 ? -1 : 0;
  arc.curvature = curvature;
  cand.curvature = arc.curvature;
  if (!arc.curvature) cand.flags |= kCandidateNoCurvature;
  // Below LENS_SIDE_ARCNESS the octopole does not tell the concave side: any side.
  const double arcness = k.arcnessColumn >= 0 ? catalog.value(best, k.arcnessColumn) : kNaN;
  std::optional<LensMatch> match;
  std::pair<double, double> lensXY;
  const std::int64_t fittedLens = lensLightOf(in, object.bestRow);
  if (fittedLens >= 0) {
    // Found in the residual of a fitted galaxy: that galaxy is the lens, at its fitted centre
    // (not pulled towards the arc, part of the galaxy's object, as its centroid is).
    cand.flags |= kCandidateLensLight;
    lensXY = {k.x(std::size_t(fittedLens)), k.y(std::size_t(fittedLens))};
    if (in.fittedCentres != nullptr) {
      const auto found = in.fittedCentres->find(std::size_t(fittedLens));
      if (found != in.fittedCentres->end()) lensXY = found->second;
    }
    match = LensMatch{std::size_t(fittedLens), std::hypot(lensXY.first - x, lensXY.second - y)};
  } else {
    if (std::abs(arcness) < s.sideMinArcness) {
      cand.flags |= kCandidateSideUnknown;
      arc.arcSide = 0;
    }
    match = findBrightestLens(arc, galaxies, k.lensRadiusPix);
    if (match) {
      for (const LensCandidateGalaxy& g : galaxies) {
        if (g.row != match->row) continue;
        lensXY = {g.x, g.y};
        if (g.inArc) cand.flags |= kCandidateLensInArc;
      }
    }
  }
  if (match) {
    cand.lens = describeLens(k, object, cand, *match, lensXY, arc);
  } else {
    cand.flags |= kCandidateDarkLens;
  }
  return cand;
}

// COLOUR_CUT: removes the candidates whose arc minus lens colour exceeds the cut's MAX.
void applyColourCut(const SearchSettings& s, SearchResult& result) {
  if (!s.colourCut) return;
  const auto band = std::find(s.colourBands.begin(), s.colourBands.end(), s.colourCut->band);
  const std::size_t magIndex = std::size_t(band - s.colourBands.begin()) + 1;
  const auto removed = std::remove_if(
      result.candidates.begin(), result.candidates.end(), [&](const Candidate& cand) {
        return failsColourCut(cand, magIndex, s.colourCut->maxArcMinusLensMag);
      });
  result.summary.removedByColourCut = std::int64_t(result.candidates.end() - removed);
  result.candidates.erase(removed, result.candidates.end());
}

}  // namespace

SearchResult searchCandidates(const SearchInput& in, const SearchSettings& s) {
  checkSearchInput(in, s);
  const bool trees = s.method == SelectionMethod::Trees;
  const Table& catalog = *in.catalog;
  const SearchColumns c(catalog);
  const std::int64_t n = catalog.rows();
  if (in.lensLightOf != nullptr && std::int64_t(in.lensLightOf->size()) != n) {
    throw ConfigError("search: the lens-light marks do not match the catalog's rows");
  }

  const GridScores grid = trees ? GridScores{{}, std::vector<bool>(std::size_t(n), true)}
                                : gridScores(*in.grid, catalog);
  const std::vector<RowScore>& scores = grid.scores;
  std::vector<std::vector<bool>> spaceMasks;
  for (const SearchSpace& space : s.reportSpaces) spaceMasks.push_back(space.mask(catalog));

  SearchResult result;
  SearchSummary& summary = result.summary;
  summary.searchedPixels = in.mask->searchedPixelCount();
  // Without a WCS, from the pixel scale (a flat, square-pixel sky).
  summary.searchedAreaDeg2 =
      in.wcs != nullptr ? in.mask->searchedAreaDeg2(*in.wcs)
                        : double(summary.searchedPixels) * std::pow(s.pixelScaleArcsec / 3600.0, 2);
  const ScoredRows rows = selectScoredRows(in, s, c, summary);
  const std::vector<TreeRow>& tree = rows.tree;
  const std::vector<std::int64_t>& scored = rows.scored;
  summary.rowsScored = std::int64_t(scored.size());
  summary.priorFraction =
      searchPriorFraction(s.lensDensityPerDeg2, summary.searchedAreaDeg2, summary.rowsScored,
                          trees ? in.model->training.arcRowsPerSystem : 1.0);
  const std::vector<double> lensScore = lensScores(in, s, scored, scores, summary);
  const std::vector<bool> passed =
      passedRows(s, scored, lensScore, grid, spaceMasks, std::size_t(n), summary);

  const std::vector<MergedObject> objects = mergeAcrossLevels(tree, passed, lensScore);
  const double lensRadiusPix = s.lensRadiusArcsec / s.pixelScaleArcsec;
  const RowCells nearby(catalog, c, tree, lensRadiusPix);
  const std::vector<std::optional<CircleFit>> curvatures = curvaturesOf(in, objects, tree);
  const std::vector<double> fluxMax = columnValues(catalog, "FLUX_MAX");
  const std::vector<std::size_t> peaks = brightestPeaks(tree, rows.rowOf, fluxMax);
  int maxLevel = 1;
  for (const TreeRow& t : tree) maxLevel = std::max(maxLevel, t.level);
  const RowIndex index{tree, rows.rowOf};
  const CandidateContext context{in,
                                 s,
                                 catalog,
                                 c,
                                 tree,
                                 rows.rowOf,
                                 nearby,
                                 index,
                                 peaks,
                                 fluxMax,
                                 lensScore,
                                 scores,
                                 spaceMasks,
                                 catalog.findColumn("ARCNESS"),
                                 maxLevel,
                                 lensRadiusPix,
                                 kInArcPeakMinArcsec / s.pixelScaleArcsec};
  for (std::size_t k = 0; k < objects.size(); ++k) {
    result.candidates.push_back(makeCandidate(context, objects[k], curvatures[k]));
  }
  if (in.residualRowsAreExtra) dropResidualDuplicates(catalog, c, s, result.candidates);
  if (!s.colourBands.empty()) {
    addColours(in, s, c, index, nearby, lensRadiusPix, result.candidates);
  }
  applyColourCut(s, result);
  countCandidates(s, result);
  return result;
}

}  // namespace octarc
