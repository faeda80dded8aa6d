#include "octarc/catalog/Catalog.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "FitsColumns.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {

namespace {

// A printf conversion split into its parts, e.g. "%+6.2f" -> flags "+", width 6, precision 2, 'f'.
struct PrintfSpec {
  std::string flags;
  int width = -1;
  int precision = -1;
  char conversion = 0;
};

bool parsePrintf(const std::string& format, PrintfSpec& out) {
  std::size_t i = 0;
  if (format.empty() || format[i++] != '%') return false;
  while (i < format.size() && std::strchr("-+ #0", format[i]) != nullptr) out.flags += format[i++];
  auto number = [&](int& value) {
    if (i >= format.size() || !std::isdigit(static_cast<unsigned char>(format[i]))) return;
    value = 0;
    while (i < format.size() && std::isdigit(static_cast<unsigned char>(format[i]))) {
      value = value * 10 + (format[i++] - '0');
    }
  };
  number(out.width);
  if (i < format.size() && format[i] == '.') {
    ++i;
    out.precision = 0;
    number(out.precision);
  }
  while (i < format.size() && std::strchr("hlLqjzt", format[i]) != nullptr) ++i;
  if (i + 1 != format.size()) return false;
  out.conversion = format[i];
  return std::strchr("dieEfgG", out.conversion) != nullptr;
}

// One column's ASCII conversion, parsed once: the printf format rebuilt without length
// modifiers plus the one the stored value needs.
class AsciiFormat {
 public:
  explicit AsciiFormat(const ColumnSpec& column) : type_(column.type) {
    PrintfSpec spec;
    if (!parsePrintf(column.printfFormat, spec)) {
      throw ConfigError("catalog column " + column.name + ": unsupported printf format '" +
                        column.printfFormat + "'");
    }
    format_ = "%" + spec.flags;
    // NaN prints as plain "nan" in the column's width: C's "+nan" / "-nan" are read as text by
    // STILTS (TOPCAT), which then types the whole column as a string.
    nanFormat_ = std::string("%") + (spec.flags.find('-') != std::string::npos ? "-" : "") +
                 (spec.width >= 0 ? std::to_string(spec.width) : "") + "s";
    if (spec.width >= 0) format_ += std::to_string(spec.width);
    if (spec.precision >= 0) format_ += "." + std::to_string(spec.precision);
    integerConversion_ = spec.conversion == 'd' || spec.conversion == 'i';
    if (integerConversion_) {
      format_ += "lld";
    } else {
      format_ += spec.conversion;
    }
  }
  // Appends the value as the column's storage type holds it (integers rounded and clamped,
  // floats rounded to float first).
  void append(double value, std::string& text) const {
    const bool integerColumn = detail::isIntegerType(type_);
    double stored = value;
    if (integerColumn) {
      stored = double(detail::integerValue(type_, value));
    } else {
      stored = storedFloatValue(type_, value);  // print what the FITS column holds
    }
    char buffer[128];
    if (!integerColumn && std::isnan(stored)) {
      std::snprintf(buffer, sizeof buffer, nanFormat_.c_str(), "nan");
    } else if (integerConversion_) {
      const long long integer = integerColumn ? static_cast<long long>(stored)
                                              : detail::integerValue(ColumnType::Int64, stored);
      std::snprintf(buffer, sizeof buffer, format_.c_str(), integer);
    } else {
      std::snprintf(buffer, sizeof buffer, format_.c_str(), stored);
    }
    text += buffer;
  }

 private:
  ColumnType type_;
  std::string format_;
  std::string nanFormat_;
  bool integerConversion_ = false;
};

// The rows of one part, in output order.
detail::TableRows partRows(const CatalogPart& part, std::size_t index) {
  if (part.objects == nullptr) {
    throw std::invalid_argument("catalog part " + std::to_string(index + 1) + " has no table");
  }
  if (part.rowOrder != nullptr && std::int64_t(part.rowOrder->size()) != part.objects->rows()) {
    throw std::invalid_argument("catalog part " + std::to_string(index + 1) +
                                ": the row order does not list every row once");
  }
  return {part.objects, part.rowOrder};
}

void checkSameColumns(const std::string& path, const std::vector<CatalogPart>& parts) {
  const Table& first = *partRows(parts.front(), 0).table;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const Table* t = partRows(parts[p], p).table;
    bool same = t->columnCount() == first.columnCount();
    for (int c = 0; same && c < t->columnCount(); ++c) {
      same = t->columns()[std::size_t(c)].name == first.columns()[std::size_t(c)].name &&
             t->columns()[std::size_t(c)].type == first.columns()[std::size_t(c)].type &&
             t->columns()[std::size_t(c)].repeat == first.columns()[std::size_t(c)].repeat;
    }
    if (!same) {
      throw ConfigError(path + ": image extension " + std::to_string(p + 1) +
                        " has other catalog columns than the first one");
    }
  }
}

void checkColumns(const Table& table) {
  for (const ColumnSpec& c : table.columns()) {
    PrintfSpec spec;
    if (!parsePrintf(c.printfFormat, spec)) {
      throw ConfigError("catalog column " + c.name + ": unsupported printf format '" +
                        c.printfFormat + "'");
    }
    if (c.repeat < 1) throw ConfigError("catalog column " + c.name + ": vector size must be >= 1");
  }
}

// --- FITS ----------------------------------------------------------------------------------

void setComment(fitsfile* f, const char* key, const char* comment, const std::string& path) {
  int status = 0;
  fits_modify_comment(f, key, comment, &status);
  detail::throwIfFitsError(status, path, std::string("cannot write keyword ") + key);
}

// Empty primary HDU: SIMPLE, BITPIX 8, NAXIS 0, EXTEND, with SExtractor's comments.
void writePrimary(fitsfile* f, const std::vector<std::string>& extraCards,
                  const std::string& path) {
  int status = 0;
  fits_create_img(f, BYTE_IMG, 0, nullptr, &status);
  detail::throwIfFitsError(status, path, "cannot write primary header");
  // cfitsio adds two COMMENT cards about the FITS definition; SExtractor's primary has none.
  while (status == 0) fits_delete_key(f, "COMMENT", &status);
  status = 0;
  fits_clear_errmsg();
  setComment(f, "SIMPLE", "This is a FITS file", path);
  setComment(f, "BITPIX", "", path);
  setComment(f, "NAXIS", "", path);
  setComment(f, "EXTEND", "This file may contain FITS extensions", path);
  for (const std::string& card : extraCards) {
    fits_write_record(f, formatPlainCard(card).c_str(), &status);
    detail::throwIfFitsError(status, path, "cannot write primary header");
  }
}

// A binary table with SExtractor's (LDACTOOLS) template: EXTNAME right after TFIELDS, the
// structural keywords commented as SExtractor does.
void createTable(fitsfile* f, const std::string& extname, std::int64_t rows,
                 const std::vector<std::string>& names, const std::vector<std::string>& tforms,
                 const std::string& path) {
  std::vector<char*> ttype;
  std::vector<char*> tform;
  for (const std::string& s : names) ttype.push_back(const_cast<char*>(s.c_str()));
  for (const std::string& s : tforms) tform.push_back(const_cast<char*>(s.c_str()));
  int status = 0;
  fits_create_tbl(f, BINARY_TBL, LONGLONG(rows), int(names.size()), ttype.data(), tform.data(),
                  nullptr, nullptr, &status);
  detail::throwIfFitsError(status, path, "cannot create table " + extname);
  // The new HDU goes to disk before its header grows: cfitsio 4.2 fails ("tried to move past end
  // of file") when inserting cards needs a new header block in a table not yet flushed.
  fits_flush_file(f, &status);
  detail::throwIfFitsError(status, path, "cannot create table " + extname);
  const std::string card = formatCard("EXTNAME", extname, "TABLE NAME");
  fits_insert_record(f, 9, card.c_str(), &status);  // after XTENSION..TFIELDS
  detail::throwIfFitsError(status, path, "cannot create table " + extname);
  setComment(f, "XTENSION", "THIS IS A BINARY TABLE (FROM THE LDACTOOLS)", path);
  setComment(f, "BITPIX", "", path);
  setComment(f, "NAXIS", "", path);
  setComment(f, "NAXIS1", "BYTES PER ROW", path);
  setComment(f, "NAXIS2", "NUMBER OF ROWS", path);
  setComment(f, "PCOUNT", "RANDOM PARAMETER COUNT", path);
  setComment(f, "GCOUNT", "GROUP COUNT", path);
  setComment(f, "TFIELDS", "FIELDS PER ROWS", path);
}

// One objects table holding the rows of `tables` in order (all with the same columns).
void writeObjects(fitsfile* f, const std::string& extname,
                  const std::vector<detail::TableRows>& tables, const std::string& path) {
  const Table& first = *tables.front().table;
  std::vector<std::string> names;
  std::vector<std::string> tforms;
  for (const ColumnSpec& c : first.columns()) {
    names.push_back(c.name);
    tforms.push_back(tformOf(c));
  }
  std::int64_t rows = 0;
  for (const detail::TableRows& t : tables) rows += t.rows();
  // Created empty so that the column cards can still be inserted cheaply; the rows come after.
  createTable(f, extname, 0, names, tforms, path);
  for (int c = 0; c < first.columnCount(); ++c) {
    detail::writeColumnCards(f, c + 1, first.columns()[std::size_t(c)], path);
  }
  // The header is final: declare the rows and let cfitsio re-read the HDU's layout, so that the
  // rows below are written once, straight after the header. (Inserting rows instead would first
  // write the whole data area full of zeros.)
  int status = 0;
  fits_modify_key_lng(f, "NAXIS2", LONGLONG(rows), "&", &status);
  fits_set_hdustruc(f, &status);
  detail::throwIfFitsError(status, path, "cannot write table " + extname);
  // Several parts (FITS_1.0, or one table per level) follow each other in the one table.
  detail::writeTableRows(f, tables, path);
}

// The LDAC_IMHEAD cell: the image cards, the run cards and END, 80 characters each.
std::string imheadCell(const FitsHeader& imageHeader, const std::vector<std::string>& runCards) {
  std::string cell;
  for (const std::string& card : imageHeader.cards) {
    if (card.compare(0, 8, "END     ") == 0 || card == "END") continue;
    cell += formatPlainCard(card);
  }
  for (const std::string& card : runCards) cell += formatPlainCard(card);
  cell += formatPlainCard("END");
  return cell;
}

// LDAC_IMHEAD: one row, one column holding the image cards, the run cards and END.
void writeImhead(fitsfile* f, const CatalogPart& part, const std::string& path) {
  std::string cell = imheadCell(part.imageHeader, part.runCards);
  const std::size_t ncards = cell.size() / 80;

  createTable(f, "LDAC_IMHEAD", 1, {"Field Header Card"}, {std::to_string(cell.size()) + "A"},
              path);
  int status = 0;
  fits_modify_record(f, 10, formatCard("TTYPE1", std::string("Field Header Card")).c_str(),
                     &status);
  fits_modify_record(f, 11, formatCard("TFORM1", std::to_string(cell.size()) + "A").c_str(),
                     &status);
  const std::string tdim = "(80, " + std::to_string(ncards) + ")";
  fits_insert_record(f, 12, formatCard("TDIM1", tdim).c_str(), &status);
  detail::throwIfFitsError(status, path, "cannot write LDAC_IMHEAD header");
  fits_write_tblbytes(f, 1, 1, LONGLONG(cell.size()), reinterpret_cast<unsigned char*>(cell.data()),
                      &status);
  detail::throwIfFitsError(status, path, "cannot write LDAC_IMHEAD");
}

void writeFits(const std::string& path, CatalogType type, const std::vector<CatalogPart>& parts,
               const std::vector<std::string>& fits10PrimaryCards) {
  AtomicFile out(path);
  fitsfile* created = nullptr;
  int status = 0;
  // The disk-file variant: a directory name with '(' or '[' is not taken for cfitsio syntax.
  fits_create_diskfile(&created, out.tempPath().c_str(), &status);
  detail::throwIfFitsError(status, path, "cannot create");
  detail::FitsPtr file(created);
  fitsfile* f = file.get();
  if (type == CatalogType::FitsLdac) {
    writePrimary(f, {}, path);
    for (std::size_t p = 0; p < parts.size(); ++p) {
      writeImhead(f, parts[p], path);
      writeObjects(f, "LDAC_OBJECTS", {partRows(parts[p], p)}, path);
    }
  } else {
    writePrimary(f, fits10PrimaryCards, path);
    std::vector<detail::TableRows> tables;
    for (std::size_t p = 0; p < parts.size(); ++p) tables.push_back(partRows(parts[p], p));
    writeObjects(f, "OBJECTS", tables, path);
  }
  detail::closeWritten(file.release(), path);
  out.commit();
}

void writeLdacTablesAt(const std::string& path, const std::vector<std::string>& runCards,
                       const std::vector<NamedTable>& tables) {
  fitsfile* created = nullptr;
  int status = 0;
  fits_create_diskfile(&created, path.c_str(), &status);
  detail::throwIfFitsError(status, path, "cannot create");
  detail::FitsPtr file(created);
  fitsfile* f = file.get();
  writePrimary(f, {}, path);
  CatalogPart head;
  head.runCards = runCards;
  writeImhead(f, head, path);
  for (const NamedTable& t : tables) {
    checkColumns(*t.table);
    writeObjects(f, t.extname, {{t.table, nullptr}}, path);
  }
  detail::closeWritten(file.release(), path);
}

// --- ASCII ---------------------------------------------------------------------------------

void writeAscii(const std::string& path, bool withHeader, const std::vector<CatalogPart>& parts) {
  AtomicFile out(path);
  std::FILE* file = std::fopen(out.tempPath().c_str(), "w");
  if (file == nullptr) throw IoError(path + ": cannot create (" + std::strerror(errno) + ")");
  std::string text;
  const Table& first = *partRows(parts.front(), 0).table;
  if (withHeader) {
    int index = 1;
    char line[256];
    for (const ColumnSpec& c : first.columns()) {
      std::snprintf(line, sizeof line, "# %3d %-22.22s %-58.58s", index, c.name.c_str(),
                    c.description.c_str());
      text += line;
      if (!c.unit.empty()) text += " [" + c.unit + "]";
      text += '\n';
      index += c.repeat;
    }
  }
  bool ok = std::fwrite(text.data(), 1, text.size(), file) == text.size();
  std::vector<AsciiFormat> formats;
  for (const ColumnSpec& c : first.columns()) formats.emplace_back(c);
  for (std::size_t p = 0; p < parts.size() && ok; ++p) {
    const detail::TableRows rows = partRows(parts[p], p);
    const Table& t = *rows.table;
    for (std::int64_t k = 0; k < rows.rows() && ok; ++k) {
      const std::int64_t r = rows.rowAt(k);
      text.clear();
      for (int c = 0; c < t.columnCount(); ++c) {
        for (int e = 0; e < t.columns()[std::size_t(c)].repeat; ++e) {
          if (!text.empty()) text += ' ';
          formats[std::size_t(c)].append(t.value(r, c, e), text);
        }
      }
      text += '\n';
      ok = std::fwrite(text.data(), 1, text.size(), file) == text.size();
    }
  }
  ok = (std::fclose(file) == 0) && ok;
  if (!ok) throw IoError(path + ": cannot write (" + std::strerror(errno) + ")");
  out.commit();
}

}  // namespace

CatalogType parseCatalogType(const std::string& keyword) {
  const std::string k = uppercase(keyword);
  if (k == "FITS_LDAC") return CatalogType::FitsLdac;
  if (k == "FITS_1.0") return CatalogType::Fits10;
  if (k == "ASCII_HEAD") return CatalogType::AsciiHead;
  if (k == "ASCII") return CatalogType::Ascii;
  if (k == "NONE") return CatalogType::None;
  if (k == "ASCII_SKYCAT" || k == "ASCII_VOTABLE" || k == "FITS_TPX") {
    throw ConfigError("CATALOG_TYPE " + keyword +
                      ": not supported (use FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII or NONE)");
  }
  throw ConfigError("CATALOG_TYPE " + keyword +
                    ": unknown catalog type (FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII or NONE)");
}

std::string catalogTypeName(CatalogType type) {
  switch (type) {
    case CatalogType::FitsLdac:
      return "FITS_LDAC";
    case CatalogType::Fits10:
      return "FITS_1.0";
    case CatalogType::AsciiHead:
      return "ASCII_HEAD";
    case CatalogType::Ascii:
      return "ASCII";
    case CatalogType::None:
      break;
  }
  return "NONE";
}

std::string tdispFromPrintf(const std::string& printfFormat) {
  PrintfSpec spec;
  if (!parsePrintf(printfFormat, spec) || spec.width < 0) return {};
  char code = 0;
  switch (spec.conversion) {
    case 'd':
    case 'i':
      code = 'I';
      break;
    case 'f':
      code = 'F';
      break;
    case 'e':
    case 'E':
      code = 'E';
      break;
    default:
      code = 'G';
      break;
  }
  std::string out = code + std::to_string(spec.width);
  if (spec.precision >= 0) out += "." + std::to_string(spec.precision);
  return out;
}

std::string tformOf(const ColumnSpec& column) {
  char code = 'E';
  switch (column.type) {
    case ColumnType::Int16:
      code = 'I';
      break;
    case ColumnType::Int32:
      code = 'J';
      break;
    case ColumnType::Int64:
      code = 'K';
      break;
    case ColumnType::Float32:
      code = 'E';
      break;
    case ColumnType::Float64:
      code = 'D';
      break;
  }
  return std::to_string(column.repeat) + code;
}

std::string formatAsciiValue(const ColumnSpec& column, double value) {
  std::string text;
  AsciiFormat(column).append(value, text);
  return text;
}

void writeCatalog(const std::string& path, CatalogType type, const std::vector<CatalogPart>& parts,
                  const std::vector<std::string>& fits10PrimaryCards) {
  if (type == CatalogType::None) return;
  if (parts.empty()) throw std::invalid_argument("writeCatalog: no catalog part");
  checkSameColumns(path, parts);
  checkColumns(*partRows(parts.front(), 0).table);
  switch (type) {
    case CatalogType::FitsLdac:
    case CatalogType::Fits10:
      writeFits(path, type, parts, fits10PrimaryCards);
      break;
    case CatalogType::AsciiHead:
    case CatalogType::Ascii:
      writeAscii(path, type == CatalogType::AsciiHead, parts);
      break;
    case CatalogType::None:
      break;
  }
}

FitsTable ldacImheadTable(const FitsHeader& imageHeader, const std::vector<std::string>& runCards) {
  const std::string cell = imheadCell(imageHeader, runCards);
  FitsTable table;
  table.name = "LDAC_IMHEAD";
  FitsColumn column;
  column.name = "Field Header Card";
  column.repeat = int(cell.size());
  column.dimensions = "(80, " + std::to_string(cell.size() / 80) + ")";
  column.values = std::vector<std::string>{cell};
  table.columns.push_back(std::move(column));
  return table;
}

void writeLdacTables(const std::string& path, const std::vector<std::string>& runCards,
                     const std::vector<NamedTable>& tables) {
  writeLdacTablesAt(path, runCards, tables);
}

}  // namespace octarc
