// Shared steps of the measure and detect commands: the column plan from a .param file, the
// measurement of a list of segments into table rows, ASSOC matching, and the run's header cards.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "octarc/catalog/RunSummary.h"
#include "octarc/core/Segment.h"
#include "octarc/core/Table.h"
#include "octarc/io/Wcs.h"
#include "octarc/measure/MeasureContext.h"
#include "octarc/measure/Registry.h"
#include "octarc/sexcompat/Assoc.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

struct RunSettings;
struct PreparedImage;

// What the catalog will hold: the user's columns in .param order, plus what octarc needs
// internally (X_IMAGE/Y_IMAGE for ASSOC) and drops before writing.
struct ColumnPlan {
  MeasurementPlan plan;                   // every measured column, output ones first
  std::vector<ColumnSpec> outputColumns;  // what the catalog holds, in .param order
  int assocVectorSize = 0;                // VECTOR_ASSOC(n); 0 when ASSOC is off
  bool assoc = false;                     // VECTOR_ASSOC or NUMBER_ASSOC requested
};

// Reads PARAMETERS_NAME and builds the plan; warns "catalog parameter unknown" for unknown
// names (on stderr unless quiet), as SExtractor does. A catalog of several levels (levelCount >
// 1) always holds THRESH_LEVEL, without which its rows could not be told apart: when the .param
// file lacks it, it is added after NUMBER (first when there is no NUMBER), with a warning.
ColumnPlan planColumns(const RunSettings& settings, bool quiet, int levelCount = 1);

// Measures every segment into `table` (columns = plan.plan.columns()), one row per segment in
// the given order, on `threads` threads; the result does not depend on the thread count.
void measureSegments(const MeasurementPlan& plan, const std::vector<Segment>& segments,
                     const MeasureContext& context, Table& table, int threads);

// Loads the ASSOC list (ASSOC_NAME; through this image's WCS when ASSOCCOORD_TYPE is WORLD),
// fills VECTOR_ASSOC / NUMBER_ASSOC and applies ASSOCSELEC_TYPE (rows not kept are removed),
// unless `keepAllRows` (columns appended to an existing catalog keep its rows).
// `table` has the full plan's columns.
void applyAssoc(const sexcompat::AssocSettings& settings, int vectorSize,
                const PreparedImage& image, Table& table, bool quiet, bool keepAllRows = false);

// The catalog table the user asked for: the output columns of `full`, in .param order.
Table outputTable(const ColumnPlan& plan, const Table& full);
// The same, taking over `full` when it holds exactly the output columns.
Table outputTable(const ColumnPlan& plan, Table&& full);

// LDAC_IMHEAD cards after the image header: SExtractor's SEx* keywords followed by octarc's
// OCT* keywords (levels, background and noise origin).
struct RunFacts {
  std::string imagePath;
  int extension = 0, extensionCount = 1;
  double elapsedSec = 0.0;
  std::int64_t detectedCount = 0, finalCount = 0;
  int parameterCount = 0;
};
RunSummary runSummary(const RunSettings& settings, const PreparedImage& image,
                      const std::vector<ThresholdLevel>& levels, const RunFacts& facts);
std::vector<std::string> runHeaderCards(const RunSummary& summary, const PreparedImage& image,
                                        const std::vector<ThresholdLevel>& levels);
// octarc's own cards of runHeaderCards: OCTNLEV, OCTTHn, OCTBKSRC, OCTSGSRC.
std::vector<std::string> octarcRunCards(const PreparedImage& image,
                                        const std::vector<ThresholdLevel>& levels);
// The cards of runHeaderCards that a SExtractor catalog with octarc's columns appended gets as
// provenance: SEXGAIN, SEXBKGND, SEXBKDEV (added only where the catalog has none, see
// catalog/AppendedCatalog.h) and octarc's own.
std::vector<std::string> appendedRunCards(const RunSummary& summary, const PreparedImage& image,
                                          const std::vector<ThresholdLevel>& levels);

// WRITE_XML: what a detect or measure run adds to its settings and configuration for the XML
// run summary (catalog/RunXml.h).
struct XmlRunFacts {
  std::string commandLine;                // as typed, e.g. "octarc detect a.fits -c x.sex"
  std::vector<RunSummary> extensions;     // one per image extension
  std::vector<std::int64_t> levelCounts;  // thresholds per extension
  std::vector<std::string> warnings;      // printed (or, when QUIET, not) during the run
  double durationSec = 0.0;
};
// The XML text: the catalog's columns, each extension's counts, every key of `schema` with its
// value in `config`.
std::string runXmlText(const RunSettings& settings, const sexcompat::Config& config,
                       const std::vector<sexcompat::KeySpec>& schema,
                       const std::vector<ColumnSpec>& columns, const XmlRunFacts& facts);

// `context` with its WCS replaced by a copy held in `storage`: a WCS serialises its
// transforms, so each measuring thread uses its own.
MeasureContext withOwnWcs(const MeasureContext& context, std::optional<Wcs>& storage);

}  // namespace octarc
