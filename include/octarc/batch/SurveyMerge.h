// The survey-level candidate catalog of a batch: the tiles' candidates in one table, those seen
// twice in the overlap of two tiles kept once, and the searched area of the survey as the union
// of the tiles' searched areas.
//
// Duplicates: candidates of different tiles closer on the sky than the match radius are one
// object; the copy kept is the one nearest its own tile's centre (the tile that saw it best,
// far from an edge), ties going to the earlier tile. A kept copy stands for at most one copy of
// each other tile: two candidates of one tile stay two objects. Union: each block of searched
// pixels (SearchMask::kAreaBlockPix on a side) counts for the part of it that no earlier tile
// searched (the block of the earlier tile holding that sky position has searched pixels); where an
// earlier tile's edge crosses a block, the block is divided down to the pixels along the edge.
// Tiles without a celestial WCS cannot be matched on the sky: their candidates are all kept and
// their area (from the pixel scale) added.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/io/FitsTable.h"
#include "octarc/io/Wcs.h"

namespace octarc {

struct TileCandidates {
  std::string name;
  FitsTable candidates;  // the tile's LDAC_OBJECTS (search/CandidateTable.h)
  std::optional<Wcs> wcs;
  std::int64_t widthPix = 0, heightPix = 0;
  Image<std::int32_t> searchedBlocks;  // searched pixels per block
  std::int64_t blockPix = 64;
  double pixelScaleArcsec = 0.0;  // for the area of a tile without WCS
};

struct SpaceTotal {
  std::string name, expression;
  std::int64_t candidates = 0;
};

struct SurveyCandidates {
  // NUMBER (1.. by LENS_SCORE over the survey), TILE, TILE_NUMBER (NUMBER in its tile), then
  // the tiles' columns but NUMBER, LENS_RANK being the survey's rank (= NUMBER).
  FitsTable table;
  std::int64_t tileCandidates = 0;        // before duplicates are removed
  std::int64_t duplicatesRemoved = 0;     // copies dropped
  double areaDeg2 = 0.0;                  // the union of searched areas
  std::vector<SpaceTotal> spaces;         // the tiles' report spaces, counted over the survey
  std::vector<std::int64_t> keptPerTile;  // candidates each tile contributes
};

// Merges the tiles (in manifest order). ConfigError when two tiles' tables have different
// columns (made by other configurations).
SurveyCandidates mergeTiles(const std::vector<TileCandidates>& tiles, double matchRadiusArcsec);

}  // namespace octarc
