#include "octarc/batch/SurveyMerge.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/search/Search.h"
#include "octarc/selection/SearchMask.h"

namespace octarc {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 unitVector(double raDeg, double decDeg) {
  const double a = raDeg * kRadPerDeg, d = decDeg * kRadPerDeg;
  return {std::cos(d) * std::cos(a), std::cos(d) * std::sin(a), std::sin(d)};
}

double chord2(const Vec3& a, const Vec3& b) {
  const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

// The chord between two points `angleDeg` apart on the unit sphere.
double chordOf(double angleDeg) {
  return 2.0 * std::sin(0.5 * angleDeg * kRadPerDeg);
}

// A tile's footprint on the sky: its centre and the radius that holds its corners.
struct Footprint {
  bool onSky = false;
  Vec3 centre{};
  double radiusChord = 0.0;
};

Footprint footprintOf(const TileCandidates& t) {
  Footprint f;
  if (!t.wcs) return f;
  const auto c = t.wcs->pixelToWorld(0.5 * double(t.widthPix + 1), 0.5 * double(t.heightPix + 1));
  if (!std::isfinite(c[0]) || !std::isfinite(c[1])) return f;
  f.onSky = true;
  f.centre = unitVector(c[0], c[1]);
  const double xs[2] = {0.5, double(t.widthPix) + 0.5}, ys[2] = {0.5, double(t.heightPix) + 0.5};
  for (const double x : xs) {
    for (const double y : ys) {
      const auto w = t.wcs->pixelToWorld(x, y);
      if (std::isfinite(w[0]) && std::isfinite(w[1])) {
        f.radiusChord =
            std::max(f.radiusChord, std::sqrt(chord2(f.centre, unitVector(w[0], w[1]))));
      }
    }
  }
  return f;
}

// True when tile u searched the block holding world position (lng, lat).
bool searchedAt(const TileCandidates& u, double lng, double lat) {
  const auto p = u.wcs->worldToPixel(lng, lat);
  if (!std::isfinite(p[0]) || !std::isfinite(p[1])) return false;
  const double x = fromFitsPixel(p[0]) + 0.5, y = fromFitsPixel(p[1]) + 0.5;  // 0-based edges
  if (!(x >= 0 && y >= 0 && x < double(u.widthPix) && y < double(u.heightPix))) return false;
  return u.searchedBlocks(std::int64_t(x) / u.blockPix, std::int64_t(y) / u.blockPix) > 0;
}

// The fraction of the pixel rectangle [x0, x1] x [y0, y1] (1-based pixel edges) of `tile` that
// none of the `earlier` tiles searched. Its corners and centre decide when they agree; else the
// rectangle is halved along each side, down to single pixels, so that an earlier tile's edge
// across a block is followed to the pixel at the cost of the pixels along it.
double uncoveredFraction(const std::vector<TileCandidates>& tiles,
                         const std::vector<std::size_t>& earlier, const TileCandidates& tile,
                         double x0, double y0, double x1, double y1) {
  const auto covered = [&](double x, double y) {
    const auto w = tile.wcs->pixelToWorld(x, y);
    return std::any_of(earlier.begin(), earlier.end(),
                       [&](std::size_t u) { return searchedAt(tiles[u], w[0], w[1]); });
  };
  const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
  if (x1 - x0 <= 1.0 && y1 - y0 <= 1.0) return covered(xm, ym) ? 0.0 : 1.0;
  // Probes half a pixel inside the corners: the centres of the corner pixels.
  const std::array<std::array<double, 2>, 5> probes = {{{x0 + 0.5, y0 + 0.5},
                                                        {x1 - 0.5, y0 + 0.5},
                                                        {x0 + 0.5, y1 - 0.5},
                                                        {x1 - 0.5, y1 - 0.5},
                                                        {xm, ym}}};
  int hits = 0;
  for (const auto& p : probes) hits += covered(p[0], p[1]);
  if (hits == 0) return 1.0;
  if (hits == int(probes.size())) return 0.0;
  // Halves on whole pixels.
  const double xs = x1 - x0 > 1.0 ? x0 + std::floor(0.5 * (x1 - x0)) : x1;
  const double ys = y1 - y0 > 1.0 ? y0 + std::floor(0.5 * (y1 - y0)) : y1;
  double free = 0.0;
  for (const auto& [ax, bx] : {std::pair{x0, xs}, std::pair{xs, x1}}) {
    for (const auto& [ay, by] : {std::pair{y0, ys}, std::pair{ys, y1}}) {
      if (bx <= ax || by <= ay) continue;
      free += (bx - ax) * (by - ay) * uncoveredFraction(tiles, earlier, tile, ax, ay, bx, by);
    }
  }
  return free / ((x1 - x0) * (y1 - y0));
}

double unionAreaDeg2(const std::vector<TileCandidates>& tiles,
                     const std::vector<Footprint>& footprints) {
  double area = 0.0;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const TileCandidates& tile = tiles[t];
    if (!footprints[t].onSky) {
      std::int64_t pixels = 0;
      for (const std::int32_t c : tile.searchedBlocks.pixels()) pixels += c;
      area += double(pixels) * std::pow(tile.pixelScaleArcsec / 3600.0, 2);
      continue;
    }
    std::vector<std::size_t> earlier;  // earlier tiles that may overlap this one
    for (std::size_t u = 0; u < t; ++u) {
      if (!footprints[u].onSky) continue;
      const double reach = footprints[t].radiusChord + footprints[u].radiusChord;
      if (chord2(footprints[t].centre, footprints[u].centre) <= reach * reach) earlier.push_back(u);
    }
    // The part of each block that no earlier tile searched.
    const auto share = [&](std::int64_t bx, std::int64_t by) {
      if (earlier.empty()) return 1.0;
      const double x0 = double(bx * tile.blockPix) + 0.5;  // 1-based edges of the block
      const double y0 = double(by * tile.blockPix) + 0.5;
      const double x1 = double(std::min((bx + 1) * tile.blockPix, tile.widthPix)) + 0.5;
      const double y1 = double(std::min((by + 1) * tile.blockPix, tile.heightPix)) + 0.5;
      return uncoveredFraction(tiles, earlier, tile, x0, y0, x1, y1);
    };
    area += searchedAreaDeg2(tile.searchedBlocks, tile.blockPix, tile.widthPix, tile.heightPix,
                             *tile.wcs, share);
  }
  return area;
}

// Appends row `row` of `from` to `to` (the same column type).
void appendValue(FitsColumn& to, const FitsColumn& from, std::int64_t row) {
  std::visit(
      [&](const auto& source) {
        using V = std::decay_t<decltype(source)>;
        if constexpr (std::is_same_v<V, std::monostate>) {
          return;
        } else if constexpr (std::is_same_v<V, std::vector<std::string>>) {
          std::get<V>(to.values).push_back(source[std::size_t(row)]);
        } else {
          const std::size_t n = std::size_t(std::max(1, from.repeat));
          auto& out = std::get<V>(to.values);
          out.insert(out.end(), source.begin() + std::ptrdiff_t(std::size_t(row) * n),
                     source.begin() + std::ptrdiff_t((std::size_t(row) + 1) * n));
        }
      },
      from.values);
}

// A column of the same name, description, unit, display and type as `c`, with no rows.
FitsColumn emptyLike(const FitsColumn& c) {
  FitsColumn out = c;
  out.values = std::visit(
      [](const auto& v) -> FitsColumnValues { return std::decay_t<decltype(v)>(); }, c.values);
  out.tform.clear();
  if (c.type() == FitsColumnType::String) out.repeat = 0;  // as wide as the longest value
  return out;
}

std::string columnSignature(const FitsTable& t) {
  std::string s;
  for (const FitsColumn& c : t.columns) {
    // Vector lengths too: LEVELS holds as many elements as the tile's run has levels.
    s += c.name + ":" + std::string(fitsColumnTypeName(c.type())) +
         (c.type() == FitsColumnType::String ? "" : "[" + std::to_string(c.repeat) + "]") + ";";
  }
  return s;
}

struct Copy {
  std::size_t tile = 0;
  std::int64_t row = 0;
};

}  // namespace

SurveyCandidates mergeTiles(const std::vector<TileCandidates>& tiles, double matchRadiusArcsec) {
  SurveyCandidates out;
  std::vector<Footprint> footprints;
  for (const TileCandidates& t : tiles) footprints.push_back(footprintOf(t));
  out.areaDeg2 = unionAreaDeg2(tiles, footprints);
  out.keptPerTile.assign(tiles.size(), 0);

  // Every tile's candidates, with their sky positions.
  const FitsTable* schema = nullptr;
  std::vector<Copy> copies;
  std::vector<Vec3> where;
  std::vector<bool> onSky;
  std::vector<double> score, centreChord;
  std::vector<std::int64_t> tileNumber;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const FitsTable& table = tiles[t].candidates;
    if (!schema) {
      schema = &table;
    } else if (columnSignature(table) != columnSignature(*schema)) {
      throw ConfigError("tile " + tiles[t].name + ": its candidate table has other columns than " +
                        "tile " + tiles.front().name + "'s (made with another configuration?)");
    }
    const std::int64_t n = table.rows();
    const std::vector<double> ra = table.doubles("ALPHA_J2000"), dec = table.doubles("DELTA_J2000");
    const std::vector<double> prob = table.doubles("LENS_SCORE");
    const std::vector<std::int64_t> number = table.integers("NUMBER");
    for (std::int64_t r = 0; r < n; ++r) {
      copies.push_back({t, r});
      const bool sky = footprints[t].onSky && std::isfinite(ra[std::size_t(r)]) &&
                       std::isfinite(dec[std::size_t(r)]);
      onSky.push_back(sky);
      where.push_back(sky ? unitVector(ra[std::size_t(r)], dec[std::size_t(r)]) : Vec3{});
      centreChord.push_back(sky ? chord2(where.back(), footprints[t].centre) : 0.0);
      score.push_back(prob[std::size_t(r)]);
      tileNumber.push_back(number[std::size_t(r)]);
    }
  }
  out.tileCandidates = std::int64_t(copies.size());

  // Copies are taken best first (nearest their tile's centre, then the earlier tile, then the
  // row). A copy closer than the radius to a kept copy of another tile is that object seen
  // again, unless that kept copy already holds a copy from this copy's tile: two candidates of
  // one tile are two objects, even when another tile's copy lies between them. Near copies are
  // found through a grid of cells of the radius's size.
  std::vector<std::size_t> order(copies.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(centreChord[a], copies[a].tile, copies[a].row) <
           std::tie(centreChord[b], copies[b].tile, copies[b].row);
  });
  const double radiusChord = chordOf(matchRadiusArcsec / 3600.0);
  const auto cellOf = [&](const Vec3& v) {
    return std::array<std::int64_t, 3>{std::int64_t(std::floor(v[0] / radiusChord)),
                                       std::int64_t(std::floor(v[1] / radiusChord)),
                                       std::int64_t(std::floor(v[2] / radiusChord))};
  };
  std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> keptCells;
  std::vector<std::set<std::size_t>> tilesHeld(copies.size());  // per kept copy
  std::vector<std::size_t> kept;
  for (const std::size_t i : order) {
    bool duplicate = false;
    if (onSky[i] && radiusChord > 0) {
      const auto c = cellOf(where[i]);
      for (std::int64_t dx = -1; dx <= 1 && !duplicate; ++dx) {
        for (std::int64_t dy = -1; dy <= 1 && !duplicate; ++dy) {
          for (std::int64_t dz = -1; dz <= 1 && !duplicate; ++dz) {
            const auto it = keptCells.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == keptCells.end()) continue;
            for (const std::size_t k : it->second) {
              if (copies[k].tile == copies[i].tile || tilesHeld[k].count(copies[i].tile)) continue;
              if (chord2(where[i], where[k]) <= radiusChord * radiusChord) {
                tilesHeld[k].insert(copies[i].tile);
                duplicate = true;
                break;
              }
            }
          }
        }
      }
    }
    if (duplicate) continue;
    kept.push_back(i);
    tilesHeld[i].insert(copies[i].tile);
    if (onSky[i] && radiusChord > 0) keptCells[cellOf(where[i])].push_back(i);
  }
  out.duplicatesRemoved = out.tileCandidates - std::int64_t(kept.size());
  // Survey order: by LENS_SCORE (NaN last), then tile, then the tile's own order.
  std::sort(kept.begin(), kept.end(), [&](std::size_t a, std::size_t b) {
    const double pa = std::isnan(score[a]) ? -INFINITY : score[a];
    const double pb = std::isnan(score[b]) ? -INFINITY : score[b];
    if (pa != pb) return pa > pb;
    return std::tie(copies[a].tile, tileNumber[a]) < std::tie(copies[b].tile, tileNumber[b]);
  });

  // The table.
  FitsTable& table = out.table;
  table.name = "LDAC_OBJECTS";
  FitsColumn number;
  number.name = "NUMBER";
  number.comment = "Candidate number over the survey, by LENS_SCORE";
  number.display = "I7";
  number.values = std::vector<std::int32_t>();
  FitsColumn tileName;
  tileName.name = "TILE";
  tileName.comment = "Tile the candidate was kept from (its folder tiles/TILE)";
  tileName.repeat = 0;
  tileName.values = std::vector<std::string>();
  FitsColumn tileNumberColumn;
  tileNumberColumn.name = "TILE_NUMBER";
  tileNumberColumn.comment = "NUMBER of the candidate in its tile's catalog";
  tileNumberColumn.display = "I6";
  tileNumberColumn.values = std::vector<std::int32_t>();
  table.columns = {number, tileName, tileNumberColumn};
  std::vector<std::size_t> sourceColumns;
  if (schema) {
    for (std::size_t c = 0; c < schema->columns.size(); ++c) {
      if (schema->columns[c].name == "NUMBER") continue;
      sourceColumns.push_back(c);
      table.columns.push_back(emptyLike(schema->columns[c]));
    }
  }
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const Copy& copy = copies[kept[k]];
    const FitsTable& from = tiles[copy.tile].candidates;
    std::get<std::vector<std::int32_t>>(table.columns[0].values).push_back(std::int32_t(k + 1));
    std::get<std::vector<std::string>>(table.columns[1].values).push_back(tiles[copy.tile].name);
    std::get<std::vector<std::int32_t>>(table.columns[2].values)
        .push_back(std::int32_t(tileNumber[kept[k]]));
    for (std::size_t c = 0; c < sourceColumns.size(); ++c) {
      FitsColumn& column = table.columns[3 + c];
      // The rank is the survey's, as NUMBER.
      if (column.name == "LENS_RANK") {
        std::get<std::vector<std::int32_t>>(column.values).push_back(std::int32_t(k + 1));
      } else {
        appendValue(column, from.columns[sourceColumns[c]], copy.row);
      }
    }
    ++out.keptPerTile[copy.tile];
  }

  // The report spaces, as the tiles name them (SPNAMEn, SPEXPRn), counted over the survey.
  if (schema && schema->hasKeyword("NSPACES")) {
    const std::int64_t n = schema->integer("NSPACES", 0, kMaxReportSpaces);
    const std::vector<double> bits =
        table.findColumn("SPACES") ? table.doubles("SPACES") : std::vector<double>();
    for (std::int64_t s = 1; s <= n; ++s) {
      SpaceTotal total;
      total.name = schema->text("SPNAME" + std::to_string(s));
      total.expression = schema->text("SPEXPR" + std::to_string(s));
      for (const double v : bits) total.candidates += (std::int64_t(v) >> (s - 1)) & 1;
      out.spaces.push_back(std::move(total));
    }
  }
  return out;
}

}  // namespace octarc
