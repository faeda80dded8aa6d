#include "octarc/run/RunKeys.h"

#include <algorithm>
#include <string>

#include "octarc/core/Segment.h"
#include "octarc/sexcompat/KeyRow.h"
#include "octarc/sexcompat/Keys.h"

namespace octarc {

using sexcompat::KeySpec;

namespace {

using Kind = KeySpec::Kind;

constexpr double kBig = sexcompat::KeyRow::kBig;

using Row = sexcompat::KeyRow;

KeySpec* findIn(std::vector<KeySpec>& keys, const std::string& name) {
  auto it =
      std::find_if(keys.begin(), keys.end(), [&](const KeySpec& k) { return k.name == name; });
  return it == keys.end() ? nullptr : &*it;
}

}  // namespace

std::vector<KeySpec> octarcKeys() {
  std::vector<KeySpec> keys = sexcompat::sextractorKeys();

  KeySpec* backType = findIn(keys, "BACK_TYPE");
  backType->keywords.push_back("GLOBAL");
  backType->comment =
      "AUTO (mesh map), MANUAL (BACK_VALUE) or GLOBAL\n(one sigma-clipped level for the image)";
  // One output per INPUT_CATALOG when octarc appends columns to several catalogs.
  KeySpec* catalogName = findIn(keys, "CATALOG_NAME");
  catalogName->maxCount = 255;
  catalogName->comment =
      "output catalog file name (with INPUT_CATALOG and\nAPPEND_COLUMNS Y: one per input catalog)";
  findIn(keys, "WEIGHT_TYPE")->comment =
      "NONE, MAP_RMS, MAP_VAR or MAP_WEIGHT\n(BACKGROUND: not supported by octarc)";
  findIn(keys, "WEIGHT_GAIN")->comment = "scale the gain with the weights (octarc: Y only)";
  // Only the values octarc writes are listed; the others load (an existing .sex file stays
  // valid) and are refused by the command with a message.
  findIn(keys, "CATALOG_TYPE")->comment =
      "NONE, ASCII, ASCII_HEAD, ASCII_VOTABLE, FITS_1.0 or\nFITS_LDAC (ASCII_SKYCAT, FITS_TPX: "
      "not\n"
      "supported by octarc)";
  findIn(keys, "CHECKIMAGE_TYPE")->comment =
      "NONE, BACKGROUND, BACKGROUND_RMS, -BACKGROUND,\nFILTERED, OBJECTS or SEGMENTATION (octarc"
      " detect;\nthe other SExtractor types are not supported)";

  KeySpec* threads = findIn(keys, "NTHREADS");
  threads->defaults = {"0"};
  threads->minValue = 0;
  threads->comment = "number of threads (0 = all cores)";

  // clang-format off
  const std::vector<KeySpec> own = {
    Row("SEGMENTATION_NAME", Kind::String, {},
        "SExtractor SEGMENTATION check-image(s) to measure;\nseveral = thresholds, lowest first")
        .list(0, 255),
    Row("INPUT_CATALOG", Kind::String, {},
        "SExtractor catalog(s) of those runs (FITS_LDAC or\nFITS_1.0), one per segmentation image;"
        " octarc\ncolumns are appended to them")
        .list(0, 255),
    Row("APPEND_COLUMNS", Kind::Bool, {"Y"},
        "with INPUT_CATALOG: Y = append the octarc columns\nto each catalog (one CATALOG_NAME per"
        " input),\nN = write one new catalog of every level"),
    Row("REPLACE_INPUT_CATALOG", Kind::Bool, {"N"},
        "with APPEND_COLUMNS Y: Y lets a CATALOG_NAME equal its\nINPUT_CATALOG, which is then"
        " replaced (atomically)"),
    Row("BACKGROUND_NAME", Kind::String, {}, "SExtractor BACKGROUND check-image to subtract")
        .list(0, 1),
    Row("BACKGROUND_RMS_NAME", Kind::String, {}, "SExtractor BACKGROUND_RMS check-image (noise)")
        .list(0, 1),
    Row("DETECT_THRESH_MAX", Kind::Float, {"20"},
        "highest threshold of a multi-threshold run\n(units of DETECT_THRESH)").range(0, kBig),
    Row("DETECT_NLEVELS", Kind::Int, {"1"},
        "number of thresholds from DETECT_THRESH to\nDETECT_THRESH_MAX (logarithmic spacing;"
        " 1 = one\nlevel, as SExtractor; the arc search uses 15)")
        .range(1, kMaxThresholdLevels),
    Row("DETECT_LEVELS", Kind::Float, {},
        "explicit list of thresholds, lowest first\n(empty = use DETECT_NLEVELS)")
        .list(0, kMaxThresholdLevels),
  };
  // clang-format on
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

}  // namespace octarc
