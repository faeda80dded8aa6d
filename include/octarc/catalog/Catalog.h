// Catalog writers: SExtractor's FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII and ASCII_VOTABLE formats.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/io/FitsTable.h"

namespace octarc {

enum class CatalogType { FitsLdac, Fits10, AsciiHead, Ascii, AsciiVotable, None };

// Parses a CATALOG_TYPE value (case-insensitive): FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII,
// ASCII_VOTABLE, NONE. Throws ConfigError for ASCII_SKYCAT and FITS_TPX (known to SExtractor, not
// supported here) and for anything else.
CatalogType parseCatalogType(const std::string& keyword);

// The SExtractor spelling of a catalog type ("FITS_LDAC", "FITS_1.0", ...).
std::string catalogTypeName(CatalogType type);

// One measured image extension.
struct CatalogPart {
  FitsHeader imageHeader;             // header of the measured image (copied into LDAC_IMHEAD)
  std::vector<std::string> runCards;  // 80-char cards appended after the image cards (SEx*, OCT*)
  const Table* objects = nullptr;     // one row per object
  // The order in which the rows of `objects` are written (each row index once), e.g. by
  // threshold level while the table holds them in the order they were measured; nullptr: as
  // stored.
  const std::vector<std::int64_t>* rowOrder = nullptr;
};

// Writes a catalog atomically (temporary file + rename); CatalogType::None writes nothing.
// - FitsLdac: empty primary HDU, then one LDAC_IMHEAD/LDAC_OBJECTS pair per part.
// - Fits10: primary HDU holding `fits10PrimaryCards` (see sexFits10Cards()), then one
//   BINTABLE 'OBJECTS' holding the rows of every part in order.
// - AsciiHead/Ascii: one line per object ("# %3d %-22.22s %-58.58s [unit]" header lines first for
//   AsciiHead), every part in order.
// - AsciiVotable: a VOTable 1.3 with one TABLEDATA table of every part's rows; a FIELD per
//   column (datatype, arraysize for vectors, VO unit, UCD, description), NaN as "NaN", and each
//   part's run cards as PARAMs (in a GROUP "EXTENSION_n" per part when there are several).
// With several parts, every part must declare the same columns (ConfigError otherwise).
// Throws IoError naming `path` when it cannot be written.
void writeCatalog(const std::string& path, CatalogType type, const std::vector<CatalogPart>& parts,
                  const std::vector<std::string>& fits10PrimaryCards = {});

// A FITS-LDAC file holding several different tables after one LDAC_IMHEAD (whose cell holds
// only `runCards`): e.g. a simulation's systems (LDAC_OBJECTS) and its arc rows (ARCS).
// Written at `path` itself, not atomically: pass the temporary path of an AtomicFile that the
// caller commits (so that several files can be committed together).
struct NamedTable {
  std::string extname;
  const Table* table = nullptr;
};
void writeLdacTables(const std::string& path, const std::vector<std::string>& runCards,
                     const std::vector<NamedTable>& tables);

// The LDAC_IMHEAD table of a FITS-LDAC file written with io/FitsTable (for tables with string
// columns, which writeCatalog does not hold): one row, one cell "Field Header Card" of
// 80-character cards (TDIM (80, n)): the image header's cards, then `runCards`, then END.
FitsTable ldacImheadTable(const FitsHeader& imageHeader, const std::vector<std::string>& runCards);

// FITS TDISP value for a printf format: "%10d" -> "I10", "%11.4f" -> "F11.4", "%18.10e" ->
// "E18.10", "%12.7g" -> "G12.7", "%+6.2f" -> "F6.2". Empty when the format has no width or is
// not one of d, i, f, e, E, g, G.
std::string tdispFromPrintf(const std::string& printfFormat);

// FITS TFORM value with its repeat count: "1E", "3D", "1J"...
std::string tformOf(const ColumnSpec& column);

// SExtractor's ASCII_HEAD header: a line "# index NAME description [unit]" per column, the index
// counting vector elements.
std::string asciiHeadHeader(const std::vector<ColumnSpec>& columns);

// A text value as one blank-free word (ASCII readers split lines at blanks; "-" for empty).
std::string asciiWord(std::string text);

// One value as the ASCII catalogs print it: the column's printf format applied to the value
// converted to the column's storage type (integers as integers, floats rounded to float first).
// NaN in a floating-point column prints as "nan" in the column's width, never signed ("+nan" and
// "-nan", as printf writes them, are text to STILTS); integer columns store NaN as 0.
std::string formatAsciiValue(const ColumnSpec& column, double value);

// One value as ASCII_VOTABLE writes it in a TABLEDATA cell (VOTable 1.3, section 6): integers
// as the column stores them, floats with the digits that give back the stored float or double,
// NaN as "NaN", infinities as "+Inf" / "-Inf".
std::string formatVotableValue(const ColumnSpec& column, double value);

}  // namespace octarc
