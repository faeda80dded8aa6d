// The tiles of a survey: a manifest file, or a glob of images.
//
// A manifest is a text file of one tile per line:
//
//   IMAGE [WEIGHT [MASK [CATALOG]]]
//
// fields separated by commas (CSV) or blanks; '-' or an empty field for none; '#' starts a
// comment; a first line whose first field is "image" is a CSV header. WEIGHT is the tile's
// weight map (of the configuration's WEIGHT_TYPE), MASK a DS9 region file of its searched area
// (MASK_NAME), CATALOG an earlier detection run of it (INPUT_CATALOG). Relative paths are taken
// from the manifest's folder. A tile is named by its image's file name without the .fits (.fit,
// .fts, .fz) ending; names must differ.
//
// The manifest of a measuring batch (TASK MEASURE) has rows of SExtractor's outputs instead:
//
//   IMAGE SEGMENTATION CATALOG [WEIGHT]
//
// three or four fields: the image, the SEGMENTATION check-image and the catalog (FITS_LDAC or
// FITS_1.0) of a SExtractor run on it, and its weight map ('-' or empty for none); a header's
// first field is "image" too. No glob: each image needs its own SExtractor outputs.
//
// Instead of a manifest, a glob pattern of images ('tiles/*.fits', quoted so that the shell
// leaves it alone), in sorted order, with no mask or catalog. The weight map of NAME.fits is
// NAME.weight.fits beside it (as `octarc simulate field` writes them), never a tile itself.
#pragma once

#include <string>
#include <vector>

namespace octarc {

struct Tile {
  std::string name;  // from the image's file name
  std::string imagePath;
  std::string weightPath;        // "" for none
  std::string maskPath;          // "" for none
  std::string catalogPath;       // "" for none
  std::string segmentationPath;  // SExtractor's SEGMENTATION check-image (TASK MEASURE), or ""
  int line = 0;                  // 1-based line of the manifest (0 for a glob)
};

// The tiles of `manifestOrGlob`. ConfigError naming the manifest and line ("survey.txt:4: ...")
// for a missing or unreadable file (a glob's weight map included), a repeated image or tile name,
// too many fields, or a manifest (or glob) of no tile; IoError when the manifest itself cannot be
// read. Masks are only opened here; the batch parses them against their images before any tile is
// searched. globWeights (WEIGHT_TYPE is not NONE): a glob's tiles take their weight maps, which
// must be there; else they have none. `rows`: the layout of the rows; a MEASURE row of another
// count than 3 or 4 fields, or without its segmentation image or catalog, is a ConfigError
// naming the line, and so is a glob.
enum class ManifestRows { Search, Measure };
std::vector<Tile> readManifest(const std::string& manifestOrGlob, bool globWeights = false,
                               ManifestRows rows = ManifestRows::Search);

}  // namespace octarc
