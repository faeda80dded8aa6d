#include "octarc/catalog/Catalog.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "FitsColumns.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/catalog/RunXml.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {

namespace {

// A file being written, closed on every way out (an exception between open and close leaks no
// handle); the normal path closes it itself, to see the error of the last write.
struct CloseFile {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using OpenFile = std::unique_ptr<std::FILE, CloseFile>;

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
  OpenFile file(std::fopen(out.tempPath().c_str(), "w"));
  if (file == nullptr) throw IoError(path + ": cannot create (" + std::strerror(errno) + ")");
  std::string text;
  const Table& first = *partRows(parts.front(), 0).table;
  if (withHeader) text = asciiHeadHeader(first.columns());
  bool ok = std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
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
      ok = std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
    }
  }
  ok = (std::fclose(file.release()) == 0) && ok;
  if (!ok) throw IoError(path + ": cannot write (" + std::strerror(errno) + ")");
  out.commit();
}

// --- ASCII_VOTABLE -------------------------------------------------------------------------
// Written here by hand: Debian packages no C++ VOTable writer, and TABLEDATA is plain XML.

// One cell element as VOTable 1.3 (section 6) reads it back: integers exactly, floats with the
// digits that give back the stored float or double, NaN as "NaN" and infinities as "+Inf" and
// "-Inf".
void appendVotableValue(const ColumnSpec& column, double value, std::string& text) {
  char buffer[40];
  if (detail::isIntegerType(column.type)) {
    std::snprintf(buffer, sizeof buffer, "%lld", detail::integerValue(column.type, value));
  } else {
    const double stored = storedFloatValue(column.type, value);
    if (std::isnan(stored)) {
      std::snprintf(buffer, sizeof buffer, "NaN");
    } else if (std::isinf(stored)) {
      std::snprintf(buffer, sizeof buffer, "%s", stored > 0 ? "+Inf" : "-Inf");
    } else {
      std::snprintf(buffer, sizeof buffer, column.type == ColumnType::Float32 ? "%.9g" : "%.17g",
                    stored);
    }
  }
  text += buffer;
}

// A header card of the run ("SEXTHLD =  1.2E+01 / comment") as a VOTable PARAM: strings as
// char, T/F as boolean, integers as long and other numbers as double. Cards without a value
// (COMMENT, HISTORY) are skipped.
void appendCardParam(const std::string& card, const char* indent, std::string& text) {
  if (card.size() < 10 || card.compare(8, 2, "= ") != 0) return;
  std::string key = card.substr(0, 8);
  key.erase(key.find_last_not_of(' ') + 1);
  if (key.empty()) return;
  std::size_t i = std::min(card.find_first_not_of(' ', 10), card.size());
  std::string value;
  std::string datatype;
  if (i < card.size() && card[i] == '\'') {
    // A quoted string: '' inside is one quote; trailing blanks are not significant.
    for (++i; i < card.size(); ++i) {
      if (card[i] == '\'') {
        if (i + 1 < card.size() && card[i + 1] == '\'') {
          value += '\'';
          ++i;
          continue;
        }
        ++i;
        break;
      }
      value += card[i];
    }
    value.erase(value.find_last_not_of(' ') + 1);
    datatype = "char\" arraysize=\"*";
  } else {
    const std::size_t end = card.find('/', i);
    value = card.substr(i, end == std::string::npos ? std::string::npos : end - i);
    value.erase(value.find_last_not_of(' ') + 1);
    i = end == std::string::npos ? card.size() : end;
    if (value == "T" || value == "F") {
      datatype = "boolean";
    } else if (value.empty()) {
      datatype = "double";
      value = "NaN";  // an undefined value
    } else if (value.find_first_not_of("+-0123456789") == std::string::npos) {
      datatype = "long";
    } else {
      datatype = "double";
      std::replace(value.begin(), value.end(), 'D', 'E');  // Fortran exponent
    }
  }
  std::string comment;
  const std::size_t slash = card.find('/', i);
  if (slash != std::string::npos) {
    comment = card.substr(slash + 1);
    comment.erase(0, comment.find_first_not_of(' '));
    comment.erase(comment.find_last_not_of(' ') + 1);
  }
  text += std::string(indent) + "<PARAM name=\"" + xmlEscaped(key) + "\" datatype=\"" + datatype +
          "\" ucd=\"obs.param\" value=\"" + xmlEscaped(value) + "\"";
  if (comment.empty()) {
    text += "/>\n";
  } else {
    text += ">\n" + std::string(indent) + " <DESCRIPTION>" + xmlEscaped(comment) +
            "</DESCRIPTION>\n" + indent + "</PARAM>\n";
  }
}

void writeVotable(const std::string& path, const std::vector<CatalogPart>& parts) {
  AtomicFile out(path);
  OpenFile file(std::fopen(out.tempPath().c_str(), "w"));
  if (file == nullptr) throw IoError(path + ": cannot create (" + std::strerror(errno) + ")");
  const Table& first = *partRows(parts.front(), 0).table;
  std::string text =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<VOTABLE version=\"1.3\" xmlns=\"http://www.ivoa.net/xml/VOTable/v1.3\" "
      "xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">\n"
      "<RESOURCE name=\"octarc\">\n"
      " <DESCRIPTION>Catalog of sources extracted with octarc</DESCRIPTION>\n"
      " <TABLE name=\"LDAC_OBJECTS\">\n"
      "  <DESCRIPTION>Table of sources detected in image</DESCRIPTION>\n";
  // The run's cards (what LDAC_IMHEAD adds to the image header: thresholds, background, gain),
  // one GROUP per image extension when there are several.
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const bool grouped = parts.size() > 1;
    if (grouped) text += "  <GROUP name=\"EXTENSION_" + std::to_string(p + 1) + "\">\n";
    for (const std::string& card : parts[p].runCards) {
      appendCardParam(card, grouped ? "   " : "  ", text);
    }
    if (grouped) text += "  </GROUP>\n";
  }
  for (const ColumnSpec& c : first.columns()) {
    text +=
        "  <FIELD name=\"" + xmlEscaped(c.name) + "\" datatype=\"" + votableDatatype(c.type) + "\"";
    if (c.repeat > 1) text += " arraysize=\"" + std::to_string(c.repeat) + "\"";
    if (!c.unit.empty()) text += " unit=\"" + xmlEscaped(votableUnit(c.unit)) + "\"";
    if (!c.ucd.empty()) text += " ucd=\"" + xmlEscaped(c.ucd) + "\"";
    text += ">\n   <DESCRIPTION>" + xmlEscaped(c.description) + "</DESCRIPTION>\n  </FIELD>\n";
  }
  text += "  <DATA><TABLEDATA>\n";
  bool ok = std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
  for (std::size_t p = 0; p < parts.size() && ok; ++p) {
    const detail::TableRows rows = partRows(parts[p], p);
    const Table& t = *rows.table;
    for (std::int64_t k = 0; k < rows.rows() && ok; ++k) {
      const std::int64_t r = rows.rowAt(k);
      text = "   <TR>";
      for (int c = 0; c < t.columnCount(); ++c) {
        const ColumnSpec& column = t.columns()[std::size_t(c)];
        text += "<TD>";
        for (int e = 0; e < column.repeat; ++e) {
          if (e > 0) text += ' ';
          appendVotableValue(column, t.value(r, c, e), text);
        }
        text += "</TD>";
      }
      text += "</TR>\n";
      ok = std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
    }
  }
  text = "  </TABLEDATA></DATA>\n </TABLE>\n</RESOURCE>\n</VOTABLE>\n";
  ok = ok && std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
  ok = (std::fclose(file.release()) == 0) && ok;
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
  if (k == "ASCII_VOTABLE") return CatalogType::AsciiVotable;
  if (k == "NONE") return CatalogType::None;
  if (k == "ASCII_SKYCAT" || k == "FITS_TPX") {
    throw ConfigError(
        "CATALOG_TYPE " + keyword +
        ": not supported (use FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII, ASCII_VOTABLE or NONE)");
  }
  throw ConfigError(
      "CATALOG_TYPE " + keyword +
      ": unknown catalog type (FITS_LDAC, FITS_1.0, ASCII_HEAD, ASCII, ASCII_VOTABLE or NONE)");
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
    case CatalogType::AsciiVotable:
      return "ASCII_VOTABLE";
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

std::string formatVotableValue(const ColumnSpec& column, double value) {
  std::string text;
  appendVotableValue(column, value, text);
  return text;
}

std::string asciiHeadHeader(const std::vector<ColumnSpec>& columns) {
  std::string text;
  int index = 1;
  char line[256];
  for (const ColumnSpec& c : columns) {
    std::snprintf(line, sizeof line, "# %3d %-22.22s %-58.58s", index, c.name.c_str(),
                  c.description.c_str());
    text += line;
    if (!c.unit.empty()) text += " [" + c.unit + "]";
    text += '\n';
    index += c.repeat;
  }
  return text;
}

std::string asciiWord(std::string text) {
  std::replace(text.begin(), text.end(), ' ', '_');
  return text.empty() ? "-" : text;
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
    case CatalogType::AsciiVotable:
      writeVotable(path, parts);
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
