// Appending columns to an existing SExtractor catalog (FITS_LDAC or FITS_1.0).
//
// The output is the input catalog with new columns at the end of each objects table: every HDU,
// column, unit, TDIM and LDAC_IMHEAD card of the input is kept, and the run's provenance cards
// are added where the catalog has none of that name. Each objects table is written once: its
// header, then its rows copied from the input in large blocks with the new columns' bytes at the
// end of each row; every other HDU is copied as it is.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/Table.h"

namespace octarc {

// What goes into one objects table of the catalog.
struct AppendedColumns {
  const Table* table = nullptr;  // the new values; nullptr or no columns: nothing appended
  // The columns of `table` to append, in order; empty: every column of `table`.
  std::vector<int> columns;
  // The row of `table` that goes to each catalog row (one per row of the objects table), or
  // nullptr: row r to row r.
  const std::vector<std::int64_t>* rows = nullptr;
  // Provenance: 80-character cards added before END in the cell of the LDAC_IMHEAD of this
  // table (for a FITS_1.0 catalog, or an objects table without LDAC_IMHEAD, at the end of the
  // table's own header). A card whose keyword the catalog already has there (for FITS_1.0 also
  // in the primary header) is not added: SExtractor's own cards, and those of an earlier octarc
  // run, are never changed.
  std::vector<std::string> cards;
};

// Writes `outputPath`, atomically, from the catalog `inputPath` as readInputCatalog read it
// (`parts`), with appended[i] added to the objects table of parts[i]. `outputPath` may equal
// `inputPath`: the input is replaced only by the final rename. CHECKSUM/DATASUM of a rewritten
// HDU that had them are recomputed. ConfigError if an appended column name already exists in
// the table; IoError naming the file if the number of tables or of rows differs, if the file no
// longer matches `parts`, or if it cannot be copied (an objects table with a heap, an
// LDAC_IMHEAD that is not one cell of header cards ending with END).
void writeAppendedCatalog(const std::string& inputPath, const std::vector<InputCatalogPart>& parts,
                          const std::string& outputPath,
                          const std::vector<AppendedColumns>& appended);

// The same for whole tables without provenance cards: every column of appended[i] is added to
// the i-th objects table, row r of appended[i] going to row r of that table.
void writeAppendedCatalog(const std::string& inputPath, const std::string& outputPath,
                          const std::vector<const Table*>& appended);

}  // namespace octarc
