#include "octarc/selection/ArcContext.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

// The counter-image's window, in units of the neighbour distance, and its least opening angle.
constexpr double kCounterMinRatio = 0.25;
constexpr double kCounterMaxRatio = 1.5;
constexpr double kCounterMinAngleDeg = 135.0;

ColumnSpec contextColumn(const std::string& name, const std::string& unit,
                         const std::string& description) {
  ColumnSpec spec;
  spec.name = name;
  spec.unit = unit;
  spec.description = description;
  spec.type = ColumnType::Float32;
  spec.printfFormat = "%9.4f";
  return spec;
}

std::int64_t treeKey(double level, double number) {
  return (std::int64_t(level) << 32) | std::uint32_t(std::int64_t(number));
}

// Rows in square cells of one side (any level), to find those near a position.
class Cells {
 public:
  Cells(const std::vector<double>& x, const std::vector<double>& y, double sidePix)
      : side_(std::max(sidePix, 1.0)) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (std::isfinite(x[i]) && std::isfinite(y[i]))
        cells_[key(cell(x[i]), cell(y[i]))].push_back(i);
    }
  }
  template <typename F>
  void forEachNear(double x, double y, F&& f) const {
    const std::int64_t cx = cell(x), cy = cell(y);
    for (std::int64_t j = cy - 1; j <= cy + 1; ++j) {
      for (std::int64_t i = cx - 1; i <= cx + 1; ++i) {
        const auto found = cells_.find(key(i, j));
        if (found == cells_.end()) continue;
        for (const std::size_t row : found->second) f(row);
      }
    }
  }

 private:
  std::int64_t cell(double v) const { return std::int64_t(std::floor(v / side_)); }
  static std::uint64_t key(std::int64_t i, std::int64_t j) {
    return (std::uint64_t(i) << 32) ^ (std::uint64_t(j) & 0xffffffffu);
  }
  double side_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

}  // namespace

const std::vector<ColumnSpec>& arcContextColumns() {
  static const std::vector<ColumnSpec> columns = {
      contextColumn("CTX_NB_DIST", "arcsec", "Distance to the nearest brighter galaxy"),
      contextColumn("CTX_NB_DMAG", "mag", "Magnitude minus the nearest brighter galaxy's"),
      contextColumn("CTX_NB_DSIZE", "", "Distance to it over its sqrt(2) SIZE_IMAGE"),
      contextColumn("CTX_TANGENT", "deg", "Major axis to the tangential direction about it"),
      contextColumn("CTX_CONCAVE", "", "+1: it is on the concave side, -1 convex, 0 unknown"),
      contextColumn("CTX_COUNTER", "", "Counter-image distance from it over the row's"),
      contextColumn("CTX_COUNTER_DMAG", "mag", "Counter-image magnitude minus the row's"),
  };
  return columns;
}

const std::vector<std::string>& arcContextInputColumns() {
  static const std::vector<std::string> columns = {
      "X_IMAGE",  "Y_IMAGE",    "THRESH_LEVEL", "NUMBER",   "PARENT_NUMBER",
      "FLUX_ISO", "SIZE_IMAGE", "E1_IMAGE",     "E2_IMAGE", "ARC_SIDE"};
  return columns;
}

std::vector<double> contextValues(const ArcContext& c) {
  return {c.neighbourDistanceArcsec, c.neighbourDeltaMag, c.neighbourDistanceInSizes,
          c.tangentialAngleDeg,      c.concaveSide,       c.counterDistanceRatio,
          c.counterDeltaMag};
}

std::vector<ArcContext> arcContexts(const Table& catalog, const ArcContextSettings& settings) {
  if (!(settings.pixelScaleArcsec > 0.0)) {
    throw ConfigError("arc context: the pixel scale must be positive");
  }
  std::vector<int> col;
  for (const std::string& name : arcContextInputColumns()) {
    col.push_back(catalog.requireColumn(name, "arc context"));
  }
  const std::size_t n = std::size_t(catalog.rows());
  std::vector<double> x(n), y(n), flux(n), level(n), parent(n);
  std::unordered_map<std::int64_t, std::size_t> rowOf;
  rowOf.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = std::int64_t(i);
    x[i] = catalog.value(r, col[0]);
    y[i] = catalog.value(r, col[1]);
    level[i] = catalog.value(r, col[2]);
    parent[i] = catalog.value(r, col[4]);
    flux[i] = catalog.value(r, col[5]);
    const double number = catalog.value(r, col[3]);
    if (std::isfinite(level[i]) && std::isfinite(number)) rowOf[treeKey(level[i], number)] = i;
  }
  const double maxPix = settings.maxDistanceArcsec / settings.pixelScaleArcsec;
  // The counter-image lies up to kCounterMaxRatio neighbour distances beyond the neighbour.
  const Cells cells(x, y, maxPix * kCounterMaxRatio);
  const ArcContext none{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  std::vector<ArcContext> out(n, none);
  std::vector<std::size_t> ancestors;
  for (std::size_t i = 0; i < n; ++i) {
    // Not a row to describe: no position, no positive flux, or no place in the component tree.
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !(flux[i] > 0.0) ||
        !std::isfinite(level[i]) || !std::isfinite(parent[i])) {
      continue;
    }
    ancestors.clear();
    for (std::size_t walk = i; level[walk] > 1.0;) {
      const auto up = rowOf.find(treeKey(level[walk] - 1.0, parent[walk]));
      if (up == rowOf.end()) break;
      ancestors.push_back(up->second);
      walk = up->second;
    }
    auto isAncestor = [&](std::size_t j) {
      return std::find(ancestors.begin(), ancestors.end(), j) != ancestors.end();
    };
    std::size_t nb = n;
    double nbDist = maxPix;
    cells.forEachNear(x[i], y[i], [&](std::size_t j) {
      if (j == i || !(flux[j] > flux[i]) || isAncestor(j)) return;
      const double d = std::hypot(x[j] - x[i], y[j] - y[i]);
      if (d > kContextSameObjectPix && (d < nbDist || (d == nbDist && nb == n))) {
        nb = j;
        nbDist = d;
      }
    });
    if (nb == n) continue;
    ArcContext& c = out[i];
    const auto r = std::int64_t(i);
    c.neighbourDistanceArcsec = nbDist * settings.pixelScaleArcsec;
    c.neighbourDeltaMag = -2.5 * std::log10(flux[i] / flux[nb]);
    c.neighbourDistanceInSizes =
        nbDist / (std::sqrt(2.0) * catalog.value(std::int64_t(nb), col[6]));
    // The row's major axis against the tangential direction: the radial direction is (dx, dy).
    const double thetaRad = 0.5 * std::atan2(catalog.value(r, col[8]), catalog.value(r, col[7]));
    const double dx = x[i] - x[nb], dy = y[i] - y[nb];
    const double radialRad = std::atan2(dy, dx);
    // Angle between two axes (undirected), folded into [0, 90] deg.
    double offsetDeg = std::fmod(std::abs(thetaRad - radialRad) * kDegPerRad, 180.0);
    if (offsetDeg > 90.0) offsetDeg = 180.0 - offsetDeg;
    c.tangentialAngleDeg = 90.0 - offsetDeg;
    const double side = catalog.value(r, col[9]);
    if (side == 0.0 || !std::isfinite(side)) {
      c.concaveSide = 0.0;
    } else {
      // The neighbour's offset from the row along the row's +b axis (-sin, cos), times ARC_SIDE.
      const double along = -dx * -std::sin(thetaRad) + -dy * std::cos(thetaRad);
      c.concaveSide = along * side > 0.0 ? 1.0 : -1.0;
    }
    // The counter-image: on the neighbour's other side.
    std::size_t counter = n;
    double counterDist = 0.0;
    const double cosMin = std::cos(kCounterMinAngleDeg * kRadPerDeg);
    cells.forEachNear(x[nb], y[nb], [&](std::size_t j) {
      if (j == i || j == nb || isAncestor(j) || !(flux[j] < flux[nb]) || !(flux[j] > 0.0)) return;
      const double ex = x[j] - x[nb], ey = y[j] - y[nb];
      const double d = std::hypot(ex, ey);
      if (d <= kCounterMinRatio * nbDist || d > kCounterMaxRatio * nbDist) return;
      if ((ex * dx + ey * dy) / (d * nbDist) > cosMin) return;
      if (counter == n || flux[j] > flux[counter]) {
        counter = j;
        counterDist = d;
      }
    });
    if (counter < n) {
      c.counterDistanceRatio = counterDist / nbDist;
      c.counterDeltaMag = -2.5 * std::log10(flux[counter] / flux[i]);
    }
  }
  return out;
}

}  // namespace octarc
