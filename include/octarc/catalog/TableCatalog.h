// A FITS-style table (io/FitsTable.h: typed columns, string columns, header keywords) written as
// any catalog type: the candidate catalogs of `search` and `batch`, which hold text columns the
// measurement catalogs (catalog/Catalog.h) do not.
#pragma once

#include <map>
#include <string>

#include "octarc/catalog/Catalog.h"
#include "octarc/io/FitsTable.h"

namespace octarc {

// Writes `objects` at `path` (which must not exist: pass the temporary path of an AtomicFile or
// of a temporary output directory, committed by the caller) as
// - FitsLdac: `ldacImhead` (see ldacImheadTable()), then `objects` as LDAC_OBJECTS;
// - Fits10: `objects` alone, as the BINTABLE 'OBJECTS' after an empty primary HDU, so that a
//   reader takes it without being told which HDU;
// - AsciiHead/Ascii: one line per row ("# %3d %-22.22s %-58.58s [unit]" lines first for
//   AsciiHead, a vector numbered as one column per element), numbers in the column's TDISP
//   format, text as one word (a blank becomes '_', an empty value '-'); the keywords are not
//   written, as SExtractor's ASCII catalogs hold none;
// - AsciiVotable: a VOTable 1.3 TABLEDATA table: a FIELD per column (datatype, arraysize for
//   vectors and text, VO unit, UCD, description), the keywords as PARAMs, NaN as "NaN".
// `ucdByColumn` gives the columns' IVOA UCDs (FITS has no keyword for them; a column not listed
// has none).
// ConfigError for CatalogType::None; IoError naming `path` when it cannot be written.
void writeTableCatalog(const std::string& path, CatalogType type, const FitsTable& objects,
                       const FitsTable& ldacImhead,
                       const std::map<std::string, std::string>& ucdByColumn = {});

}  // namespace octarc
