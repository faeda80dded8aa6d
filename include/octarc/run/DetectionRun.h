// A whole detection run of a configured image, in memory: every image extension prepared,
// detected at every level and measured, ASSOC applied, the catalog's tables and header cards
// assembled. `octarc detect` and the demo call it, then write what it returns.
//
//   RunSettings + ColumnPlan --> runDetection() --> DetectionRunResult
//     --> writeCatalog(parts())      (catalog/Catalog.h)
//     --> writeCheckImages()         (the check-images, from the kept image and footprints)
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "octarc/catalog/Catalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Assoc.h"

namespace octarc {

// The CHECKIMAGE_TYPE values `octarc detect` writes.
const std::vector<std::string>& detectCheckImageTypes();

// One image extension of the run.
struct DetectedExtension {
  Table table;                      // the catalog's columns (ColumnPlan::outputColumns)
  std::vector<std::int64_t> order;  // catalog order of the rows; empty: as stored
  FitsHeader header;                // the image header
  std::vector<std::string> cards;   // the run's LDAC_IMHEAD cards (runHeaderCards)
  RunSummary summary;               // the run's values (the XML run summary, WRITE_XML)
  std::vector<ThresholdLevel> levels;
  std::vector<std::int64_t> objectsPerLevel;
};

struct DetectionRunResult {
  std::vector<DetectedExtension> extensions;
  std::vector<std::string> fits10Cards;  // the FITS_1.0 primary header cards
  // Kept for the check-images (single-extension images only): the prepared image, its
  // footprints at every level (SEGMENTATION, OBJECTS) and its levels.
  std::optional<PreparedImage> checkImage;
  std::optional<SegmentationRuns> segmentation;
  std::vector<ThresholdLevel> checkLevels;

  // The catalog parts (pointing into this result) for writeCatalog().
  std::vector<CatalogPart> parts() const;
};

// Progress and notes of a run ("> Reading ...", warnings), one line at a time; may be empty.
using RunLog = std::function<void(const std::string& line)>;

// Detects and measures settings.imagePaths[0] (every image extension) with the columns of
// `columns`; ASSOC with `assoc` when set. Keeps the image and its footprints when the settings
// ask for check-images, or with `keepImageAndFootprints` (a search, single-extension images
// only). ConfigError / IoError on bad settings or input; nothing is written.
DetectionRunResult runDetection(const RunSettings& settings, const ColumnPlan& columns,
                                const std::optional<sexcompat::AssocSettings>& assoc,
                                const RunLog& log, bool keepImageAndFootprints = false);

// The run `octarc detect IMAGE -c configPath -KEY value ...` makes, in memory and silent: the
// .sex file with `keys` (KEY, value) on top, PARAMETERS_NAME as given, ASSOC when its columns
// are asked for. Nothing is written.
DetectionRunResult runConfiguredDetection(
    const std::string& imagePath, const std::string& configPath,
    const std::vector<std::pair<std::string, std::string>>& keys);

// Writes the check-images of `result` (CHECKIMAGE_TYPE / CHECKIMAGE_NAME of `settings`), check
// image i to output firstCheck + i of `outputs`, each through at most one image-sized buffer;
// `log` gets a line when each is done. Frees buffers of `result` as it goes (OBJECTS blanks the
// measurement image in place): call it after the catalog is written.
void writeCheckImages(const RunSettings& settings, DetectionRunResult& result,
                      const OutputFiles& outputs, std::size_t firstCheck, const RunLog& log);

}  // namespace octarc
