#include "octarc/batch/BatchKeys.h"

#include <cstdlib>
#include <stdexcept>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/sexcompat/KeyRow.h"

namespace octarc {

namespace {

using sexcompat::KeySpec;
using Kind = KeySpec::Kind;

}  // namespace

std::vector<KeySpec> batchKeys() {
  std::vector<KeySpec> keys = searchKeys();
  for (KeySpec& k : keys) {
    if (k.name == "OUTPUT_DIR") {
      k.defaults = {"survey"};
      k.comment = "directory of the survey: journal, tiles/, candidates";
    } else if (k.name == "LENS_CHECKIMAGES") {
      k.defaults = {"N"};  // two image-sized files per tile: only when asked for
    } else if (k.name == "WEIGHT_IMAGE") {
      // Each tile's comes from the manifest: none here, so that a -dd template loads back.
      k.defaults = {};
      k.comment = "none: each tile's weight map is in the manifest";
    } else if (k.name == "CATALOG_TYPE") {
      k.comment =
          "format of the survey's OUTPUT_DIR/candidates.fits:\nFITS_LDAC, FITS_1.0, ASCII_HEAD, "
          "ASCII or\nASCII_VOTABLE (the tiles' stay FITS_LDAC)";
    }
  }
  // clang-format off
  const std::vector<KeySpec> own = {
    sexcompat::KeyRow("MATCH_RADIUS", Kind::Float, {"1.0"}, "candidates of two tiles closer than "
        "this are one\n(arcsec)").range(0, 60),
    sexcompat::KeyRow("ARRAY_TASK", Kind::String, {"AUTO"}, "this job-array task's share: I/N "
        "(tiles k with\nk % N == I), AUTO (Slurm's SLURM_ARRAY_TASK_ID)"),
  };
  // clang-format on
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

BatchSettings batchSettingsFromConfig(const sexcompat::Config& c, RunSettings run) {
  BatchSettings s;
  if (run.imagePaths.size() != 1) {
    throw ConfigError("batch: give one manifest (or one quoted glob of images); see -h");
  }
  s.manifest = run.imagePaths.front();
  s.requestedThreads = run.threads;
  for (const char* key : {"MASK_NAME", "INPUT_CATALOG", "WEIGHT_IMAGE"}) {
    if (c.isExplicit(key)) {
      throw ConfigError(std::string(key) + ": a batch takes each tile's files from the manifest " +
                        "(IMAGE WEIGHT MASK CATALOG per line)");
    }
  }
  if (c.count("COLOUR_IMAGE") > 0) {
    throw ConfigError(
        "COLOUR_IMAGE: a batch's manifest holds one image per tile; search the "
        "tiles one by one (octarc search) to measure colours");
  }
  if (c.isExplicit("CHECKIMAGE_TYPE") && uppercase(c.getString("CHECKIMAGE_TYPE")) != "NONE") {
    throw ConfigError("CHECKIMAGE_TYPE: a batch writes no check-images");
  }
  s.tile = searchSettingsFromConfig(c, std::move(run));
  s.outputDir = s.tile.outputDir;
  s.matchRadiusArcsec = c.getDouble("MATCH_RADIUS");
  std::string share = uppercase(c.getString("ARRAY_TASK"));
  if (share == "AUTO") {
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    const char* first = std::getenv("SLURM_ARRAY_TASK_MIN");
    if (id && count) {
      try {
        share = std::to_string(std::stoll(id) - (first ? std::stoll(first) : 0)) + "/" + count;
      } catch (const std::exception&) {
        throw ConfigError(std::string("ARRAY_TASK AUTO: SLURM_ARRAY_TASK_ID ") + id +
                          " / SLURM_ARRAY_TASK_COUNT " + count + " are not numbers");
      }
    } else {
      share = "0/1";
    }
  }
  const std::size_t slash = share.find('/');
  try {
    std::size_t used = 0;
    if (slash == std::string::npos) throw std::invalid_argument(share);
    s.arrayTask = std::stoi(share.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument(share);
    s.arrayTasks = std::stoi(share.substr(slash + 1), &used);
    if (used != share.size() - slash - 1) throw std::invalid_argument(share);
  } catch (const std::exception&) {
    throw ConfigError("ARRAY_TASK " + quoteForMessage(share) + ": give I/N (0 <= I < N) or AUTO");
  }
  if (s.arrayTasks < 1 || s.arrayTask < 0 || s.arrayTask >= s.arrayTasks) {
    throw ConfigError("ARRAY_TASK " + share + ": give I/N with 0 <= I < N");
  }
  return s;
}

}  // namespace octarc
