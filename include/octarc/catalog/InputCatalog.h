// Reading an existing SExtractor catalog (FITS_LDAC or FITS_1.0); catalog/AppendedCatalog.h
// appends columns to it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/io/FitsHeader.h"

namespace octarc {

struct InputCatalogPart {
  FitsHeader imageHeader;  // cards of the LDAC_IMHEAD cell without END (empty for FITS_1.0)
  int objectsHdu = 0;      // HDU number of the objects table, 1-based as cfitsio (primary = 1)
  std::vector<std::int64_t> numbers;     // NUMBER column, in row order
  std::vector<std::string> columnNames;  // TTYPE values, in column order
};

// One part per LDAC_OBJECTS table (with the LDAC_IMHEAD before it), or the OBJECTS table of a
// FITS_1.0 catalog. Throws IoError naming the file when it cannot be opened as FITS, holds no
// LDAC_OBJECTS/OBJECTS table, or a table has no NUMBER column. Nothing is allocated from a size
// before it is checked, and no corrupt structure is passed on: every HDU must be an IMAGE,
// BINTABLE or TABLE whose data (NAXIS1 * NAXIS2 + PCOUNT for a table) fit in the file, and an
// LDAC_IMHEAD cell must hold 80-character cards that cfitsio can parse, up to an END card;
// otherwise IoError naming the file and the HDU.
std::vector<InputCatalogPart> readInputCatalog(const std::string& path);

// The named columns (scalars, any numeric type, as double) of the table `extname` of a FITS
// catalog, in row order. IoError naming the file for a missing table or column.
std::vector<std::vector<double>> readCatalogColumns(const std::string& path,
                                                    const std::string& extname,
                                                    const std::vector<std::string>& names);

// The cards of the first LDAC_IMHEAD cell of a FITS_LDAC file (up to END), checked as
// readInputCatalog checks them; IoError naming the file otherwise.
FitsHeader readLdacImageHeader(const std::string& path);

}  // namespace octarc
