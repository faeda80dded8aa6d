// A whole measurement run of a configured image on SExtractor's segmentation check-images, in
// memory: every image extension prepared (with the input catalogs' background, noise and
// gain), the objects of every level read from the segmentation images, measured, joined to
// the input catalogs' rows by NUMBER, ASSOC applied. `octarc measure` calls it, then writes a
// new catalog (parts()) or appends the columns to each input catalog (appendedColumns()).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "octarc/catalog/AppendedCatalog.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/Table.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Assoc.h"

namespace octarc {

// The input SExtractor catalogs (INPUT_CATALOG), one per level, with their run values.
struct InputCatalogs {
  std::vector<std::vector<InputCatalogPart>> parts;   // [level][extension]
  std::vector<std::vector<CatalogRunValues>> values;  // [level][extension]
};

// Reads and checks every INPUT_CATALOG of `settings` (before any image is read).
InputCatalogs readInputCatalogs(const RunSettings& settings);

// One image extension of the run.
struct MeasuredExtension {
  // A new catalog: the output columns, every level. Appending: every measured column.
  Table table;
  FitsHeader header;
  std::vector<std::string> cards;  // new catalog: runHeaderCards; appending: appendedRunCards
  RunSummary summary;              // the run's values (the XML run summary, WRITE_XML)
  std::int64_t levelCount = 0;
  // Appending: for each level, the rows of `table` its catalog takes, in its row order.
  std::vector<std::vector<std::int64_t>> catalogRows;
};

struct MeasurementRunResult {
  std::vector<MeasuredExtension> extensions;
  std::vector<std::string> fits10Cards;
  bool append = false;  // APPEND_COLUMNS Y with INPUT_CATALOG

  // A new catalog's parts (pointing into this result) for writeCatalog().
  std::vector<CatalogPart> parts() const;
  // Appending: what the catalog of `level` (0-based) gets, per extension; columns the input
  // catalog already has are kept as they are, not appended again.
  std::vector<AppendedColumns> appendedColumns(std::size_t level, const ColumnPlan& columns,
                                               const InputCatalogs& catalogs) const;
};

// The thresholds of each level: from the input catalogs (SEXTHLD/SEXATHLD) when given,
// otherwise DETECT_LEVELS (one per segmentation image), otherwise DETECT_THRESH /
// ANALYSIS_THRESH for a single level. ConfigError / IoError when none of these gives them.
std::vector<ThresholdLevel> levelThresholds(const RunSettings& settings, double sigmaAdu,
                                            const std::vector<CatalogRunValues>& catalogs,
                                            std::size_t levelCount);

// Measures settings.imagePaths[0] on settings.segmentationPaths (and `catalogs`, which may be
// empty) with the columns of `columns`; ASSOC with `assoc` when set. Nothing is written.
MeasurementRunResult runMeasurement(const RunSettings& settings, const ColumnPlan& columns,
                                    const std::optional<sexcompat::AssocSettings>& assoc,
                                    const InputCatalogs& catalogs, const RunLog& log);

}  // namespace octarc
