#include "octarc/catalog/InputCatalog.h"

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsTable.h"
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

// Refuses a card of an LDAC_IMHEAD cell that cfitsio would not take as a header card: a byte
// that is not printable ASCII, a keyword with characters FITS does not allow, or a value that
// cfitsio cannot separate from its comment (e.g. an unclosed complex value).
void requireParsableCard(const std::string& card, std::size_t number, const std::string& where) {
  const std::string at = where + ": card " + std::to_string(number) + " ";
  std::string shown = card;
  while (!shown.empty() && shown.back() == ' ') shown.pop_back();
  std::string copy = card;  // cfitsio takes non-const buffers
  int status = 0;
  if (fftrec(copy.data(), &status) != 0) {
    fits_clear_errmsg();
    throw IoError(at + quoteForMessage(shown) + " holds a byte that is not printable ASCII");
  }
  std::string keyword = card.substr(0, 8);
  while (!keyword.empty() && keyword.back() == ' ') keyword.pop_back();
  if (!keyword.empty() && fftkey(keyword.c_str(), &status) != 0) {
    fits_clear_errmsg();
    throw IoError(at + "has the illegal keyword " + quoteForMessage(keyword));
  }
  if (card.compare(8, 2, "= ") != 0 || keyword == "HISTORY" || keyword == "COMMENT") return;
  char value[FLEN_VALUE] = {0};
  char comment[FLEN_COMMENT] = {0};
  if (ffpsvc(copy.data(), value, comment, &status) != 0) {
    fits_clear_errmsg();
    throw IoError(at + quoteForMessage(shown) + ": cfitsio cannot parse its value");
  }
}

// The cards of the LDAC_IMHEAD cell (0-based HDU `hdu`), up to (not including) END. The cell is
// copied into octarc's outputs and read as a header by SCAMP and PSFEx, so it must be a character
// column of whole 80-character cards that cfitsio can parse, and hold END: anything else is
// refused.
FitsHeader readImhead(fitsfile* f, int hdu, const std::string& path) {
  const std::string where = path + ": LDAC_IMHEAD (HDU " + std::to_string(hdu) + ")";
  int status = 0;
  int columns = 0;
  long rows = 0;
  fits_get_num_cols(f, &columns, &status);
  fits_get_num_rows(f, &rows, &status);
  detail::throwIfFitsError(status, where, "cannot read the table");
  if (rows < 1 || columns < 1) throw IoError(where + " holds no header cards");
  int typecode = 0;
  long repeat = 0;
  long width = 0;
  fits_get_coltype(f, 1, &typecode, &repeat, &width, &status);
  detail::throwIfFitsError(status, where, "cannot read its column");
  if (typecode != TSTRING || repeat < 80 || repeat % 80 != 0) {
    throw IoError(where + ": its first column is not a character column of 80-character cards");
  }
  std::string cell(std::size_t(repeat), ' ');
  fits_read_tblbytes(f, 1, 1, repeat, reinterpret_cast<unsigned char*>(cell.data()), &status);
  detail::throwIfFitsError(status, where, "cannot read the header cards");
  FitsHeader header;
  for (std::size_t at = 0; at + 80 <= cell.size(); at += 80) {
    std::string card = cell.substr(at, 80);
    // A character field may end early with ASCII NUL (FITS 4.0, section 7.3.3.1): astropy pads
    // each 80-character element so, SExtractor with blanks. Both are the same card.
    if (const std::size_t nul = card.find('\0'); nul != std::string::npos) {
      card.replace(nul, std::string::npos, 80 - nul, ' ');
    }
    if (card.compare(0, 8, "END     ") == 0) return header;
    requireParsableCard(card, header.cards.size() + 1, where);
    header.cards.push_back(std::move(card));
  }
  throw IoError(where + " has no END card");
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
    detail::throwIfFitsError(status, path, "cannot read HDU " + std::to_string(hdu - 1));
    // Every HDU, also those octarc does not read: appending copies them into the output.
    detail::requireSoundHdu(f, path);
    if (type != BINARY_TBL) continue;
    const std::string extname = readExtname(f);
    if (extname == "LDAC_IMHEAD") {
      pendingImhead = readImhead(f, hdu - 1, path);
      continue;
    }
    if (extname != "LDAC_OBJECTS" && extname != "OBJECTS") continue;

    InputCatalogPart part;
    part.imageHeader = std::move(pendingImhead);
    pendingImhead = FitsHeader();
    part.objectsHdu = hdu;
    part.columnNames = readColumnNames(f, path);
    const std::string where = extname + " table (HDU " + std::to_string(hdu - 1) + ")";
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
  const FitsTable table = readFitsTable(path, extname, names);
  std::vector<std::vector<double>> columns;
  for (const std::string& name : names) columns.push_back(table.doubles(name));
  return columns;
}

FitsHeader readLdacImageHeader(const std::string& path) {
  detail::FitsPtr file = detail::openFits(path);
  fitsfile* f = file.get();
  int status = 0;
  fits_movnam_hdu(f, BINARY_TBL, const_cast<char*>("LDAC_IMHEAD"), 0, &status);
  detail::throwIfFitsError(status, path, "no LDAC_IMHEAD table");
  detail::requireSoundHdu(f, path);
  int hdu = 0;
  fits_get_hdu_num(f, &hdu);
  return readImhead(f, hdu - 1, path);
}

}  // namespace octarc
