#include "octarc/catalog/InputCatalog.h"

#include "octarc/core/Error.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {

namespace {

std::string readExtname(fitsfile* f) {
  char value[FLEN_VALUE] = {0};
  int status = 0;
  fits_read_key_str(f, "EXTNAME", value, nullptr, &status);
  if (status != 0) {
    fits_clear_errmsg();
    return {};
  }
  return value;
}

// The cards of the LDAC_IMHEAD cell, up to (not including) END.
FitsHeader readImhead(fitsfile* f, int hdu, const std::string& path) {
  int status = 0;
  long width = 0;
  fits_read_key_lng(f, "NAXIS1", &width, nullptr, &status);
  long rows = 0;
  fits_get_num_rows(f, &rows, &status);
  detail::throwIfFitsError(status, path,
                           "cannot read LDAC_IMHEAD (HDU " + std::to_string(hdu) + ")");
  if (rows < 1 || width < 80) {
    throw IoError(path + ": LDAC_IMHEAD (HDU " + std::to_string(hdu) + ") holds no header cards");
  }
  std::string cell(std::size_t(width), ' ');
  fits_read_tblbytes(f, 1, 1, width, reinterpret_cast<unsigned char*>(cell.data()), &status);
  detail::throwIfFitsError(status, path,
                           "cannot read LDAC_IMHEAD (HDU " + std::to_string(hdu) + ")");
  FitsHeader header;
  for (std::size_t at = 0; at + 80 <= cell.size(); at += 80) {
    std::string card = cell.substr(at, 80);
    if (card.compare(0, 8, "END     ") == 0) break;
    header.cards.push_back(std::move(card));
  }
  return header;
}

std::vector<std::string> readColumnNames(fitsfile* f, const std::string& path) {
  int status = 0;
  int ncols = 0;
  fits_get_num_cols(f, &ncols, &status);
  detail::throwIfFitsError(status, path, "cannot read table columns");
  std::vector<std::string> names;
  for (int c = 1; c <= ncols; ++c) {
    char key[FLEN_KEYWORD];
    char value[FLEN_VALUE] = {0};
    fits_make_keyn("TTYPE", c, key, &status);
    fits_read_key_str(f, key, value, nullptr, &status);
    if (status == KEY_NO_EXIST) {
      status = 0;
      fits_clear_errmsg();
      value[0] = '\0';
    }
    detail::throwIfFitsError(status, path, "cannot read table columns");
    names.push_back(value);
  }
  return names;
}

}  // namespace

std::vector<InputCatalogPart> readInputCatalog(const std::string& path) {
  detail::FitsPtr file = detail::openFits(path);
  fitsfile* f = file.get();
  int status = 0;
  int nhdus = 0;
  fits_get_num_hdus(f, &nhdus, &status);
  detail::throwIfFitsError(status, path, "cannot read FITS structure");

  std::vector<InputCatalogPart> parts;
  FitsHeader pendingImhead;
  for (int hdu = 1; hdu <= nhdus; ++hdu) {
    int type = 0;
    fits_movabs_hdu(f, hdu, &type, &status);
    detail::throwIfFitsError(status, path, "cannot read HDU " + std::to_string(hdu));
    if (type != BINARY_TBL) continue;
    const std::string extname = readExtname(f);
    if (extname == "LDAC_IMHEAD") {
      pendingImhead = readImhead(f, hdu, path);
      continue;
    }
    if (extname != "LDAC_OBJECTS" && extname != "OBJECTS") continue;

    InputCatalogPart part;
    part.imageHeader = std::move(pendingImhead);
    pendingImhead = FitsHeader();
    part.objectsHdu = hdu;
    part.columnNames = readColumnNames(f, path);
    const std::string where = extname + " table (HDU " + std::to_string(hdu) + ")";
    int numberCol = 0;
    for (std::size_t c = 0; c < part.columnNames.size(); ++c) {
      if (part.columnNames[c] == "NUMBER") numberCol = int(c) + 1;
    }
    if (numberCol == 0) throw IoError(path + ": " + where + " has no NUMBER column");
    int typecode = 0;
    long repeat = 0;
    long width = 0;
    long rows = 0;
    fits_get_coltype(f, numberCol, &typecode, &repeat, &width, &status);
    fits_get_num_rows(f, &rows, &status);
    detail::throwIfFitsError(status, path, "cannot read NUMBER of " + where);
    if (repeat != 1 || typecode == TSTRING) {
      throw IoError(path + ": NUMBER column of " + where + " is not a scalar integer");
    }
    part.numbers.resize(std::size_t(rows));
    if (rows > 0) {
      int anyNull = 0;
      fits_read_col(f, TLONGLONG, numberCol, 1, 1, rows, nullptr, part.numbers.data(), &anyNull,
                    &status);
      detail::throwIfFitsError(status, path, "cannot read NUMBER of " + where);
    }
    parts.push_back(std::move(part));
  }
  if (parts.empty()) {
    throw IoError(path + ": no LDAC_OBJECTS or OBJECTS table (not a SExtractor FITS_LDAC or " +
                  "FITS_1.0 catalog)");
  }
  return parts;
}

std::vector<std::vector<double>> readCatalogColumns(const std::string& path,
                                                    const std::string& extname,
                                                    const std::vector<std::string>& names) {
  detail::FitsPtr file = detail::openFits(path);
  fitsfile* f = file.get();
  int status = 0;
  fits_movnam_hdu(f, BINARY_TBL, const_cast<char*>(extname.c_str()), 0, &status);
  detail::throwIfFitsError(status, path, "no table " + extname);
  long rows = 0;
  fits_get_num_rows(f, &rows, &status);
  detail::throwIfFitsError(status, path, "cannot read table " + extname);
  std::vector<std::vector<double>> columns;
  for (const std::string& name : names) {
    int col = 0;
    fits_get_colnum(f, CASEINSEN, const_cast<char*>(name.c_str()), &col, &status);
    detail::throwIfFitsError(status, path, "no column " + name + " in " + extname);
    std::vector<double> values(std::size_t(rows), 0.0);
    int anyNull = 0;
    if (rows > 0) {
      fits_read_col(f, TDOUBLE, col, 1, 1, LONGLONG(rows), nullptr, values.data(), &anyNull,
                    &status);
    }
    detail::throwIfFitsError(status, path, "cannot read column " + name);
    columns.push_back(std::move(values));
  }
  return columns;
}

}  // namespace octarc
