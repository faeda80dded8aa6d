#include "octarc/io/FitsTable.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {

namespace {

using detail::throwIfFitsError;

// Longest string value that fits on one card: 80 columns less "KEYWORD = ''".
constexpr std::size_t kMaxShortString = 68;
// Rows of a string column read per cfitsio call (bounds the temporary buffers).
constexpr std::int64_t kStringChunkRows = 4096;

bool sameName(std::string_view a, std::string_view b) {
  return uppercase(a) == uppercase(b);
}

std::string where(const std::string& path, std::string_view hdu) {
  return path + "[" + std::string(hdu) + "]";
}

// A column keyword such as TFORM12: one of the column roots followed by digits only.
bool isColumnKeyword(const std::string& key) {
  static const char* const kRoots[] = {"TTYPE", "TFORM", "TUNIT", "TDISP", "TNULL",
                                       "TSCAL", "TZERO", "TDIM",  "TBCOL"};
  for (const char* root : kRoots) {
    const std::string r(root);
    if (key.size() > r.size() && key.compare(0, r.size(), r) == 0 &&
        std::all_of(key.begin() + std::ptrdiff_t(r.size()), key.end(),
                    [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; })) {
      return true;
    }
  }
  return false;
}

// Keywords the writer makes itself (structure, columns, long strings) and commentary cards:
// never part of FitsTable::keywords.
bool isManagedKeyword(const std::string& key) {
  static const char* const kNames[] = {"SIMPLE", "XTENSION", "BITPIX",  "PCOUNT",   "GCOUNT",
                                       "EXTEND", "TFIELDS",  "EXTNAME", "CONTINUE", "LONGSTRN",
                                       "END",    "COMMENT",  "HISTORY", "THEAP"};
  if (key.empty()) return true;
  for (const char* name : kNames) {
    if (key == name) return true;
  }
  if (key.compare(0, 5, "NAXIS") == 0) return true;
  return isColumnKeyword(key);
}

bool isKeywordName(std::string_view key) {
  if (key.empty() || key.size() > 8) return false;
  return std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  });
}

// The shortest decimal form that reads back to the same double, always with a decimal point
// (so that it reads back as a real, not an integer), e.g. "0.257", "54.0", "1.5E-07".
std::string shortestReal(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  for (char& c : text) {
    if (c == 'e') c = 'E';
  }
  const std::size_t exponent = text.find('E');
  if (text.find('.') == std::string::npos) {
    text.insert(exponent == std::string::npos ? text.size() : exponent, ".0");
  }
  return text;
}

// ---------------------------------------------------------------------------------------------
// Writing

int cfitsioDatatype(FitsColumnType type) {
  switch (type) {
    case FitsColumnType::Int16:
      return TSHORT;
    case FitsColumnType::Int32:
      return TINT;
    case FitsColumnType::Int64:
      return TLONGLONG;
    case FitsColumnType::Float32:
      return TFLOAT;
    case FitsColumnType::Float64:
      return TDOUBLE;
    default:
      return TSTRING;
  }
}

char tformCode(FitsColumnType type) {
  switch (type) {
    case FitsColumnType::Int16:
      return 'I';
    case FitsColumnType::Int32:
      return 'J';
    case FitsColumnType::Int64:
      return 'K';
    case FitsColumnType::Float32:
      return 'E';
    case FitsColumnType::Float64:
      return 'D';
    default:
      return 'A';
  }
}

// The width a string column is written with: its repeat, or the longest value when 0.
int stringWidth(const FitsColumn& column) {
  if (column.repeat > 0) return column.repeat;
  std::size_t longest = 1;
  for (const std::string& s : std::get<std::vector<std::string>>(column.values)) {
    longest = std::max(longest, s.size());
  }
  return static_cast<int>(longest);
}

void validateColumn(const FitsColumn& column, const std::string& at) {
  if (column.name.empty()) throw IoError(at + ": a column has no name");
  const std::string what = at + " column " + column.name;
  const FitsColumnType type = column.type();
  if (type == FitsColumnType::Unsupported) throw IoError(what + ": no values");
  if (type == FitsColumnType::String) {
    if (column.repeat < 0) throw IoError(what + ": negative string width");
    const int width = stringWidth(column);
    for (const std::string& s : std::get<std::vector<std::string>>(column.values)) {
      if (s.size() > std::size_t(width)) {
        throw IoError(what + ": value '" + s + "' is longer than the column width " +
                      std::to_string(width));
      }
    }
    return;
  }
  if (column.repeat < 1) {
    throw IoError(what + ": repeat " + std::to_string(column.repeat) + " (at least 1)");
  }
  const std::size_t count = std::visit(
      [](const auto& v) -> std::size_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return 0;
        } else {
          return v.size();
        }
      },
      column.values);
  if (count % std::size_t(column.repeat) != 0) {
    throw IoError(what + ": " + std::to_string(count) + " values do not fill whole rows of " +
                  std::to_string(column.repeat));
  }
}

void validateTable(const FitsTable& table, const std::string& path) {
  const std::string at = where(path, table.name);
  if (table.name.empty()) throw IoError(path + ": a table has no name (EXTNAME)");
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    validateColumn(table.columns[i], at);
    for (std::size_t j = 0; j < i; ++j) {
      if (sameName(table.columns[i].name, table.columns[j].name)) {
        throw IoError(at + ": column name " + table.columns[i].name + " given twice");
      }
    }
    if (table.columns[i].rows() != table.columns[0].rows()) {
      throw IoError(at + " column " + table.columns[i].name + ": " +
                    std::to_string(table.columns[i].rows()) + " rows, but column " +
                    table.columns[0].name + " has " + std::to_string(table.columns[0].rows()));
    }
  }
  for (const FitsKeyword& k : table.keywords) {
    if (!isKeywordName(k.name)) {
      throw IoError(at + ": keyword name '" + k.name +
                    "' is not 1-8 characters of A-Z, 0-9, '-', '_'");
    }
    if (isManagedKeyword(k.name)) {
      throw IoError(at + ": keyword " + k.name + " is written by the table writer itself");
    }
    if (const double* v = std::get_if<double>(&k.value); v && std::isinf(*v)) {
      throw IoError(at + ": keyword " + k.name + " is infinite (FITS has no infinity)");
    }
  }
}

void writeKeyword(fitsfile* f, const FitsKeyword& k, const std::string& at) {
  int status = 0;
  const char* name = k.name.c_str();
  const char* comment = k.comment.c_str();
  if (const bool* b = std::get_if<bool>(&k.value)) {
    fits_write_key_log(f, name, *b ? 1 : 0, comment, &status);
  } else if (const std::int64_t* i = std::get_if<std::int64_t>(&k.value)) {
    fits_write_key_lng(f, name, LONGLONG(*i), comment, &status);
  } else if (const std::uint64_t* u = std::get_if<std::uint64_t>(&k.value)) {
    fits_write_key_ulng(f, name, ULONGLONG(*u), comment, &status);
  } else if (const double* d = std::get_if<double>(&k.value)) {
    if (std::isnan(*d)) {
      fits_write_key_null(f, name, comment, &status);
    } else {
      std::string text = shortestReal(*d);
      char card[FLEN_CARD] = {0};
      fits_make_key(name, text.data(), comment, card, &status);
      fits_write_record(f, card, &status);
    }
  } else {
    const std::string& s = std::get<std::string>(k.value);
    fits_write_key_longstr(f, name, s.c_str(), comment, &status);
  }
  throwIfFitsError(status, at, "cannot write keyword " + k.name);
}

// True when a string keyword needs CONTINUE cards (its quotes doubled).
bool isLongString(const FitsKeyword& k) {
  const std::string* s = std::get_if<std::string>(&k.value);
  if (s == nullptr) return false;
  return s->size() + std::size_t(std::count(s->begin(), s->end(), '\'')) > kMaxShortString;
}

// TDISPn goes right after the column's TUNITn (or TFORMn) card.
void writeDisplay(fitsfile* f, int colnum, const FitsColumn& column, const std::string& at) {
  const std::string n = std::to_string(colnum);
  int status = 0;
  char card[FLEN_CARD];
  const std::string after = (column.unit.empty() ? "TFORM" : "TUNIT") + n;
  fits_read_card(f, after.c_str(), card, &status);
  fits_insert_key_str(f, ("TDISP" + n).c_str(), column.display.c_str(), "display format", &status);
  throwIfFitsError(status, at, "cannot write TDISP of column " + column.name);
}

// TDIMn, after the column's other cards.
void writeDimensions(fitsfile* f, int colnum, const std::string& dimensions,
                     const std::string& at) {
  int status = 0;
  fits_write_key_str(f, ("TDIM" + std::to_string(colnum)).c_str(), dimensions.c_str(),
                     "dimensions of the cell", &status);
  throwIfFitsError(status, at, "cannot write TDIM" + std::to_string(colnum));
}

void writeColumnValues(fitsfile* f, int colnum, const FitsColumn& column, const std::string& at) {
  int status = 0;
  const int datatype = cfitsioDatatype(column.type());
  std::visit(
      [&](const auto& v) {
        using V = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::monostate>) {
          return;
        } else if constexpr (std::is_same_v<V, std::vector<std::string>>) {
          // A TDIM "(w, n)" makes cfitsio take each cell for n strings of w characters (an
          // LDAC_IMHEAD cell of 80-character cards): the cells are handed to it so, cut up.
          std::vector<std::string> pieces;
          const std::vector<std::string>* strings = &v;
          if (const std::size_t open = column.dimensions.find('('); open != std::string::npos) {
            const long width = std::strtol(column.dimensions.c_str() + open + 1, nullptr, 10);
            const std::size_t cell = std::size_t(stringWidth(column));
            if (width > 0 && cell % std::size_t(width) == 0) {
              for (std::string s : v) {
                s.resize(cell, ' ');
                for (std::size_t at = 0; at < cell; at += std::size_t(width)) {
                  pieces.push_back(s.substr(at, std::size_t(width)));
                }
              }
              strings = &pieces;
            }
          }
          std::vector<char*> pointers;
          pointers.reserve(strings->size());
          for (const std::string& s : *strings) pointers.push_back(const_cast<char*>(s.c_str()));
          if (!pointers.empty()) {
            fits_write_col(f, TSTRING, colnum, 1, 1, LONGLONG(pointers.size()), pointers.data(),
                           &status);
          }
        } else if (!v.empty()) {
          // cfitsio takes a non-const buffer but does not modify it.
          fits_write_col(f, datatype, colnum, 1, 1, LONGLONG(v.size()),
                         const_cast<typename V::value_type*>(v.data()), &status);
        }
      },
      column.values);
  throwIfFitsError(status, at, "cannot write column " + column.name);
}

void writeTable(fitsfile* f, const FitsTable& table, const std::string& path) {
  const std::string at = where(path, table.name);
  std::vector<std::string> names, forms, units;
  for (const FitsColumn& c : table.columns) {
    names.push_back(c.name);
    const int repeat = c.type() == FitsColumnType::String ? stringWidth(c) : c.repeat;
    forms.push_back(std::to_string(repeat) + tformCode(c.type()));
    units.push_back(c.unit);
  }
  auto pointers = [](std::vector<std::string>& v) {
    std::vector<char*> p;
    for (std::string& s : v) p.push_back(s.data());
    return p;
  };
  std::vector<char*> ttype = pointers(names), tform = pointers(forms), tunit = pointers(units);
  int status = 0;
  fits_create_tbl(f, BINARY_TBL, LONGLONG(table.rows()), int(table.columns.size()), ttype.data(),
                  tform.data(), tunit.data(), table.name.c_str(), &status);
  throwIfFitsError(status, at, "cannot create the table");
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    const FitsColumn& c = table.columns[i];
    const int colnum = int(i) + 1;
    const std::string ttypeKey = "TTYPE" + std::to_string(colnum);
    fits_update_key_str(f, ttypeKey.c_str(), c.name.c_str(), c.comment.c_str(), &status);
    throwIfFitsError(status, at, "cannot write the description of column " + c.name);
    if (!c.display.empty()) writeDisplay(f, colnum, c, at);
    if (!c.dimensions.empty()) {
      writeDimensions(f, colnum, c.dimensions, at);
    }
  }
  if (std::any_of(table.keywords.begin(), table.keywords.end(), isLongString)) {
    fits_write_key_longwarn(f, &status);
    throwIfFitsError(status, at, "cannot write LONGSTRN");
  }
  for (const FitsKeyword& k : table.keywords) writeKeyword(f, k, at);
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    writeColumnValues(f, int(i) + 1, table.columns[i], at);
  }
}

// Writes into a file just created at `path`; on any failure the file is removed (it did not
// exist before: createFits refuses to overwrite).
void writeCreated(detail::FitsPtr file, const std::string& path,
                  const std::vector<FitsTable>& tables,
                  const std::vector<std::string>& primaryCards) {
  try {
    int status = 0;
    fits_create_img(file.get(), BYTE_IMG, 0, nullptr, &status);
    for (const std::string& card : primaryCards) {
      fits_write_record(file.get(), card.c_str(), &status);
    }
    throwIfFitsError(status, path, "cannot write the primary HDU");
    for (const FitsTable& t : tables) writeTable(file.get(), t, path);
    fits_close_file(file.release(), &status);
    throwIfFitsError(status, path, "cannot finish writing");
  } catch (...) {
    file.reset();
    std::remove(path.c_str());
    throw;
  }
}

// ---------------------------------------------------------------------------------------------
// Reading

struct ColumnFormat {
  FitsColumnType type = FitsColumnType::Unsupported;
  int repeat = 0;
};

ColumnFormat columnFormat(fitsfile* f, int colnum, const std::string& at) {
  int typecode = 0;
  LONGLONG repeat = 0;
  LONGLONG width = 0;
  int status = 0;
  fits_get_eqcoltypell(f, colnum, &typecode, &repeat, &width, &status);
  throwIfFitsError(status, at, "cannot read the format of column " + std::to_string(colnum));
  ColumnFormat format;
  format.repeat = int(repeat);
  switch (typecode) {
    case TBYTE:
    case TSBYTE:
    case TSHORT:
      format.type = FitsColumnType::Int16;
      break;
    case TUSHORT:
    case TINT:
    case TLONG:
      // cfitsio reports 'J' columns as TLONG; their values are 32-bit.
      format.type = FitsColumnType::Int32;
      break;
    case TUINT:
    case TULONG:
    case TLONGLONG:
      format.type = FitsColumnType::Int64;
      break;
    case TFLOAT:
      format.type = FitsColumnType::Float32;
      break;
    case TDOUBLE:
      format.type = FitsColumnType::Float64;
      break;
    case TSTRING:
      // One string per row only ("16A"); "3A8"-style string vectors are not read.
      if (width == repeat) format.type = FitsColumnType::String;
      break;
    default:
      break;
  }
  return format;
}

// A string keyword's value and comment; KEY_NO_EXIST gives "".
std::string readStringKey(fitsfile* f, const std::string& key, std::string* comment,
                          const std::string& at) {
  char value[FLEN_VALUE] = {0};
  char text[FLEN_COMMENT] = {0};
  int status = 0;
  fits_read_key(f, TSTRING, key.c_str(), value, text, &status);
  if (status == KEY_NO_EXIST) {
    fits_clear_errmsg();
    return "";
  }
  throwIfFitsError(status, at, "cannot read " + key);
  if (comment != nullptr) *comment = text;
  return value;
}

template <typename T>
std::vector<T> readNumeric(fitsfile* f, int datatype, int colnum, std::int64_t count,
                           const std::string& at, const std::string& name) {
  std::vector<T> values(std::size_t(std::max<std::int64_t>(count, 0)));
  if (values.empty()) return values;
  int anyNull = 0;
  int status = 0;
  fits_read_col(f, datatype, colnum, 1, 1, LONGLONG(values.size()), nullptr, values.data(),
                &anyNull, &status);
  throwIfFitsError(status, at, "cannot read column " + name);
  return values;
}

std::vector<std::string> readStrings(fitsfile* f, int colnum, std::int64_t rows, int width,
                                     const std::string& at, const std::string& name) {
  std::vector<std::string> values;
  values.reserve(std::size_t(rows));
  std::vector<char> buffer(std::size_t(kStringChunkRows) * std::size_t(width + 1));
  std::vector<char*> pointers(static_cast<std::size_t>(kStringChunkRows));
  for (std::int64_t first = 0; first < rows; first += kStringChunkRows) {
    const std::int64_t n = std::min(kStringChunkRows, rows - first);
    for (std::int64_t i = 0; i < n; ++i) {
      pointers[std::size_t(i)] = buffer.data() + i * (width + 1);
    }
    int anyNull = 0;
    int status = 0;
    char empty[] = "";
    fits_read_col_str(f, colnum, LONGLONG(first + 1), 1, LONGLONG(n), empty, pointers.data(),
                      &anyNull, &status);
    throwIfFitsError(status, at, "cannot read column " + name);
    for (std::int64_t i = 0; i < n; ++i) {
      std::string value(pointers[std::size_t(i)]);
      // Trailing blanks are not significant in FITS strings (cfitsio reads "" back as " ").
      value.erase(value.find_last_not_of(' ') + 1);
      values.push_back(std::move(value));
    }
  }
  return values;
}

void readColumnValues(fitsfile* f, int colnum, std::int64_t rows, FitsColumn& column,
                      FitsColumnType type, const std::string& at) {
  const std::int64_t count = rows * column.repeat;
  switch (type) {
    case FitsColumnType::Int16:
      column.values = readNumeric<std::int16_t>(f, TSHORT, colnum, count, at, column.name);
      break;
    case FitsColumnType::Int32:
      column.values = readNumeric<std::int32_t>(f, TINT, colnum, count, at, column.name);
      break;
    case FitsColumnType::Int64:
      column.values = readNumeric<std::int64_t>(f, TLONGLONG, colnum, count, at, column.name);
      break;
    case FitsColumnType::Float32:
      column.values = readNumeric<float>(f, TFLOAT, colnum, count, at, column.name);
      break;
    case FitsColumnType::Float64:
      column.values = readNumeric<double>(f, TDOUBLE, colnum, count, at, column.name);
      break;
    case FitsColumnType::String:
      column.values = readStrings(f, colnum, rows, column.repeat, at, column.name);
      break;
    default:
      column.values = std::monostate{};
  }
}

// A column's name, description, unit, display format and format (no values yet).
FitsColumn readColumnInfo(fitsfile* f, int colnum, FitsColumnType* type, const std::string& at) {
  const std::string n = std::to_string(colnum);
  FitsColumn column;
  column.name = readStringKey(f, "TTYPE" + n, &column.comment, at);
  column.tform = readStringKey(f, "TFORM" + n, nullptr, at);
  column.unit = readStringKey(f, "TUNIT" + n, nullptr, at);
  column.display = readStringKey(f, "TDISP" + n, nullptr, at);
  column.dimensions = readStringKey(f, "TDIM" + n, nullptr, at);
  const ColumnFormat format = columnFormat(f, colnum, at);
  column.repeat = format.repeat;
  *type = format.type;
  return column;
}

// A quoted FITS string ('it''s' -> it's) from the start of `field`; *rest receives what follows
// the closing quote. Trailing blanks are not significant.
std::string unquote(std::string_view field, std::string_view* rest) {
  std::size_t i = field.find('\'');
  std::string out;
  if (i == std::string_view::npos) {
    *rest = {};
    return out;
  }
  for (++i; i < field.size(); ++i) {
    if (field[i] != '\'') {
      out.push_back(field[i]);
    } else if (i + 1 < field.size() && field[i + 1] == '\'') {
      out.push_back('\'');
      ++i;
    } else {
      break;
    }
  }
  *rest = i < field.size() ? field.substr(i + 1) : std::string_view();
  out.erase(out.find_last_not_of(' ') + 1);
  return out;
}

// The comment after a value: the text after '/', leading and trailing blanks removed.
std::string commentAfter(std::string_view rest) {
  const std::size_t slash = rest.find('/');
  if (slash == std::string_view::npos) return "";
  std::string out(rest.substr(slash + 1));
  out.erase(0, out.find_first_not_of(' '));
  out.erase(out.find_last_not_of(' ') + 1);
  return out;
}

// A string keyword starting at card `k`, with the CONTINUE cards of the long-string convention
// that follow it (a value ending in '&' continues on the next card). Returns the last card used.
int readStringKeyword(fitsfile* f, int k, int count, FitsKeyword& keyword, const std::string& at) {
  char card[FLEN_CARD] = {0};
  int status = 0;
  fits_read_record(f, k, card, &status);
  throwIfFitsError(status, at, "cannot read keyword " + keyword.name);
  std::string_view rest;
  std::string value = unquote(std::string_view(card).substr(10), &rest);
  while (!value.empty() && value.back() == '&' && k < count) {
    fits_read_record(f, k + 1, card, &status);
    throwIfFitsError(status, at, "cannot read keyword " + keyword.name);
    if (std::string_view(card).substr(0, 8) != "CONTINUE") break;
    value.pop_back();
    value += unquote(std::string_view(card).substr(8), &rest);
    keyword.comment = commentAfter(rest);
    ++k;
  }
  keyword.value = std::move(value);
  return k;
}

// A real number that is the whole of `text` (C syntax: FITS's, and a few more such as "nan").
std::optional<double> wholeReal(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return value;
}

// A non-string value as cfitsio's value field gives it: logical, integer, real (Fortran 'D'
// exponents are legal FITS), or, for complex values and for a value that only starts like a
// number (cfitsio types it by its first characters: "0.2abc"), the text as written, which the
// typed readers then refuse.
FitsKeywordValue parseKeywordValue(std::string text, char type) {
  while (!text.empty() && text.back() == ' ') text.pop_back();
  if (type == 'L') return text.find('T') != std::string::npos;
  if (type == 'I') {
    const char* begin = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
    const char* end = text.data() + text.size();
    std::int64_t i = 0;
    if (const auto r = std::from_chars(begin, end, i); r.ec == std::errc() && r.ptr == end) {
      return i;
    }
    std::uint64_t u = 0;
    if (const auto r = std::from_chars(begin, end, u); r.ec == std::errc() && r.ptr == end) {
      return u;
    }
    if (const std::optional<double> d = wholeReal(text)) return *d;
    return text;
  }
  if (type == 'F') {
    std::string s = text;
    std::replace(s.begin(), s.end(), 'D', 'E');
    std::replace(s.begin(), s.end(), 'd', 'e');
    if (const std::optional<double> d = wholeReal(s)) return *d;
    return text;
  }
  return text;
}

std::vector<FitsKeyword> readKeywords(fitsfile* f, const std::string& at) {
  int count = 0;
  int more = 0;
  int status = 0;
  fits_get_hdrspace(f, &count, &more, &status);
  throwIfFitsError(status, at, "cannot read the header");
  std::vector<FitsKeyword> keywords;
  for (int k = 1; k <= count; ++k) {
    char key[FLEN_KEYWORD] = {0};
    char value[FLEN_VALUE] = {0};
    char comment[FLEN_COMMENT] = {0};
    fits_read_keyn(f, k, key, value, comment, &status);
    throwIfFitsError(status, at, "cannot read header card " + std::to_string(k));
    if (isManagedKeyword(key)) continue;
    FitsKeyword keyword{key, std::numeric_limits<double>::quiet_NaN(), comment};
    if (value[0] != '\0') {  // an empty value field is an undefined value: NaN
      char type = 0;
      fits_get_keytype(value, &type, &status);
      throwIfFitsError(status, at, std::string("cannot read keyword ") + key);
      if (type == 'C') {
        k = readStringKeyword(f, k, count, keyword, at);
      } else {
        keyword.value = parseKeywordValue(value, type);
      }
    }
    keywords.push_back(std::move(keyword));
  }
  return keywords;
}

std::string extnameOf(fitsfile* f) {
  char value[FLEN_VALUE] = {0};
  int status = 0;
  fits_read_key(f, TSTRING, "EXTNAME", value, nullptr, &status);
  if (status != 0) {
    fits_clear_errmsg();
    return "";
  }
  return value;
}

// EXTNAMEs of the binary tables of an open file; leaves the file on its last HDU.
std::vector<std::string> tableNames(fitsfile* f, const std::string& path) {
  int count = 0;
  int status = 0;
  fits_get_num_hdus(f, &count, &status);
  throwIfFitsError(status, path, "cannot count HDUs");
  std::vector<std::string> names;
  for (int hdu = 1; hdu <= count; ++hdu) {
    int type = 0;
    fits_movabs_hdu(f, hdu, &type, &status);
    throwIfFitsError(status, path, "cannot read HDU " + std::to_string(hdu - 1));
    if (type == BINARY_TBL) names.push_back(extnameOf(f));
  }
  return names;
}

void moveToTable(fitsfile* f, const std::string& path, std::string_view hduName) {
  int status = 0;
  fits_movnam_hdu(f, BINARY_TBL, const_cast<char*>(std::string(hduName).c_str()), 0, &status);
  if (status == 0) return;
  fits_clear_errmsg();
  std::string list;
  for (const std::string& name : tableNames(f, path)) {
    list += (list.empty() ? "" : ", ") + (name.empty() ? std::string("(unnamed)") : name);
  }
  throw IoError(path + ": no binary table named " + std::string(hduName) +
                (list.empty() ? " (the file has no binary table)" : " (tables: " + list + ")"));
}

// cfitsio only notices a short file when the rows are read; checking up front names the rows.
void requireCompleteTable(fitsfile* f, std::int64_t rows, const std::string& at) {
  LONGLONG headStart = 0;
  LONGLONG dataStart = 0;
  LONGLONG dataEnd = 0;
  int status = 0;
  fits_get_hduaddrll(f, &headStart, &dataStart, &dataEnd, &status);
  throwIfFitsError(status, at, "cannot locate the table data");
  long rowBytes = 0;
  fits_read_key(f, TLONG, "NAXIS1", &rowBytes, nullptr, &status);
  throwIfFitsError(status, at, "cannot read NAXIS1");
  const LONGLONG fileBytes = f->Fptr->filesize;
  if (dataEnd <= fileBytes) return;
  const LONGLONG held = rowBytes > 0 ? std::max<LONGLONG>(0, fileBytes - dataStart) / rowBytes : 0;
  throw IoError(at + ": file is truncated: the table has " + std::to_string(rows) + " rows of " +
                std::to_string(rowBytes) + " bytes, the file holds " +
                std::to_string(std::min<LONGLONG>(held, rows)) + " complete rows");
}

bool listed(const std::vector<std::string>& names, const std::string& name) {
  return std::any_of(names.begin(), names.end(),
                     [&](const std::string& c) { return sameName(c, name); });
}

// The table of the current HDU of `f`: its keywords and the chosen columns (every column when
// both lists are empty); each of `onlyColumns` must exist.
FitsTable readCurrentTable(fitsfile* f, const std::string& path,
                           const std::vector<std::string>& onlyColumns,
                           const std::vector<std::string>& optionalColumns) {
  FitsTable table;
  table.source = path;
  table.name = extnameOf(f);
  const std::string at = table.where();
  LONGLONG rows = 0;
  int columnCount = 0;
  int status = 0;
  fits_get_num_rowsll(f, &rows, &status);
  fits_get_num_cols(f, &columnCount, &status);
  throwIfFitsError(status, at, "cannot read the table size");
  requireCompleteTable(f, rows, at);
  table.keywords = readKeywords(f, at);
  const bool all = onlyColumns.empty() && optionalColumns.empty();
  for (int colnum = 1; colnum <= columnCount; ++colnum) {
    FitsColumnType type = FitsColumnType::Unsupported;
    FitsColumn column = readColumnInfo(f, colnum, &type, at);
    if (!all && !listed(onlyColumns, column.name) && !listed(optionalColumns, column.name)) {
      continue;
    }
    readColumnValues(f, colnum, rows, column, type, at);
    table.columns.push_back(std::move(column));
  }
  for (const std::string& name : onlyColumns) {
    if (table.findColumn(name) == nullptr) throw IoError(at + ": no column " + name);
  }
  return table;
}

// ---------------------------------------------------------------------------------------------
// Accessor helpers

template <typename T>
std::vector<T> widen(const FitsColumnValues& values) {
  return std::visit(
      [](const auto& v) -> std::vector<T> {
        using V = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::monostate> ||
                      std::is_same_v<V, std::vector<std::string>>) {
          return {};
        } else {
          return std::vector<T>(v.begin(), v.end());
        }
      },
      values);
}

bool isInteger(FitsColumnType t) {
  return t == FitsColumnType::Int16 || t == FitsColumnType::Int32 || t == FitsColumnType::Int64;
}

}  // namespace

// -----------------------------------------------------------------------------------------------

std::string_view fitsColumnTypeName(FitsColumnType type) {
  switch (type) {
    case FitsColumnType::Int16:
      return "int16";
    case FitsColumnType::Int32:
      return "int32";
    case FitsColumnType::Int64:
      return "int64";
    case FitsColumnType::Float32:
      return "float32";
    case FitsColumnType::Float64:
      return "float64";
    case FitsColumnType::String:
      return "string";
    default:
      return "unsupported";
  }
}

FitsColumnType FitsColumn::type() const {
  // The variant's alternatives are in the order of the enumerators.
  return static_cast<FitsColumnType>(values.index());
}

std::int64_t FitsColumn::rows() const {
  if (const auto* s = std::get_if<std::vector<std::string>>(&values)) {
    return std::int64_t(s->size());
  }
  if (repeat < 1) return 0;
  const std::size_t count = std::visit(
      [](const auto& v) -> std::size_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return 0;
        } else {
          return v.size();
        }
      },
      values);
  return std::int64_t(count) / repeat;
}

FitsKeyword FitsKeyword::logical(std::string name, bool value, std::string comment) {
  return {std::move(name), value, std::move(comment)};
}
FitsKeyword FitsKeyword::integer(std::string name, std::int64_t value, std::string comment) {
  return {std::move(name), value, std::move(comment)};
}
FitsKeyword FitsKeyword::unsignedInteger(std::string name, std::uint64_t value,
                                         std::string comment) {
  return {std::move(name), value, std::move(comment)};
}
FitsKeyword FitsKeyword::real(std::string name, double value, std::string comment) {
  return {std::move(name), value, std::move(comment)};
}
FitsKeyword FitsKeyword::text(std::string name, std::string value, std::string comment) {
  return {std::move(name), std::move(value), std::move(comment)};
}

std::string FitsTable::where() const {
  return octarc::where(source, name);
}

std::int64_t FitsTable::rows() const {
  for (const FitsColumn& c : columns) {
    const FitsColumnType type = c.type();
    if (type == FitsColumnType::String || (type != FitsColumnType::Unsupported && c.repeat > 0)) {
      return c.rows();
    }
  }
  return 0;
}

const FitsColumn* FitsTable::findColumn(std::string_view columnName) const {
  for (const FitsColumn& c : columns) {
    if (c.name == columnName) return &c;
  }
  const FitsColumn* found = nullptr;
  for (const FitsColumn& c : columns) {
    if (sameName(c.name, columnName)) {
      if (found != nullptr) return nullptr;  // ambiguous
      found = &c;
    }
  }
  return found;
}

const FitsColumn& FitsTable::column(std::string_view columnName) const {
  const FitsColumn* c = findColumn(columnName);
  if (c == nullptr) throw IoError(where() + ": no column " + std::string(columnName));
  if (c->type() == FitsColumnType::Unsupported) {
    throw IoError(where() + " column " + c->name + ": format TFORM = '" + c->tform +
                  "' is not supported");
  }
  return *c;
}

namespace {

const FitsColumn& checkedColumn(const FitsTable& t, std::string_view name, bool integerOnly,
                                int repeat) {
  const FitsColumn& c = t.column(name);
  const FitsColumnType type = c.type();
  if (type == FitsColumnType::String || (integerOnly && !isInteger(type))) {
    throw IoError(t.where() + " column " + c.name + " is " + std::string(fitsColumnTypeName(type)) +
                  ", expected " + (integerOnly ? "an integer" : "a numeric") + " column");
  }
  if (repeat > 0 && c.repeat != repeat) {
    throw IoError(t.where() + " column " + c.name + " has " + std::to_string(c.repeat) +
                  " elements per row, expected " + std::to_string(repeat));
  }
  return c;
}

}  // namespace

std::vector<double> FitsTable::doubles(std::string_view columnName, int repeat) const {
  return widen<double>(checkedColumn(*this, columnName, false, repeat).values);
}

std::vector<std::int64_t> FitsTable::integers(std::string_view columnName, int repeat) const {
  return widen<std::int64_t>(checkedColumn(*this, columnName, true, repeat).values);
}

std::vector<std::string> FitsTable::strings(std::string_view columnName) const {
  const FitsColumn& c = column(columnName);
  if (c.type() != FitsColumnType::String) {
    throw IoError(where() + " column " + c.name + " is " +
                  std::string(fitsColumnTypeName(c.type())) + ", expected a string column");
  }
  return std::get<std::vector<std::string>>(c.values);
}

const FitsKeyword* FitsTable::findKeyword(std::string_view keyword) const {
  for (const FitsKeyword& k : keywords) {
    if (sameName(k.name, keyword)) return &k;
  }
  return nullptr;
}

namespace {

const FitsKeyword& requiredKeyword(const FitsTable& t, std::string_view keyword) {
  const FitsKeyword* k = t.findKeyword(keyword);
  if (k == nullptr) throw IoError(t.where() + ": keyword " + std::string(keyword) + " missing");
  return *k;
}

[[noreturn]] void wrongKeywordType(const FitsTable& t, const FitsKeyword& k, const char* what) {
  throw IoError(t.where() + ": keyword " + k.name + " is not " + what);
}

}  // namespace

double FitsTable::number(std::string_view keyword) const {
  const FitsKeyword& k = requiredKeyword(*this, keyword);
  if (const double* d = std::get_if<double>(&k.value)) return *d;
  if (const std::int64_t* i = std::get_if<std::int64_t>(&k.value)) return double(*i);
  if (const std::uint64_t* u = std::get_if<std::uint64_t>(&k.value)) return double(*u);
  wrongKeywordType(*this, k, "a number");
}

std::int64_t FitsTable::integer(std::string_view keyword) const {
  const FitsKeyword& k = requiredKeyword(*this, keyword);
  if (const std::int64_t* i = std::get_if<std::int64_t>(&k.value)) return *i;
  wrongKeywordType(*this, k, "a 64-bit signed integer");
}

std::uint64_t FitsTable::unsignedInteger(std::string_view keyword) const {
  const FitsKeyword& k = requiredKeyword(*this, keyword);
  if (const std::uint64_t* u = std::get_if<std::uint64_t>(&k.value)) return *u;
  if (const std::int64_t* i = std::get_if<std::int64_t>(&k.value); i && *i >= 0) {
    return std::uint64_t(*i);
  }
  wrongKeywordType(*this, k, "a non-negative integer");
}

bool FitsTable::logical(std::string_view keyword) const {
  const FitsKeyword& k = requiredKeyword(*this, keyword);
  if (const bool* b = std::get_if<bool>(&k.value)) return *b;
  wrongKeywordType(*this, k, "a logical (T/F)");
}

std::string FitsTable::text(std::string_view keyword) const {
  const FitsKeyword& k = requiredKeyword(*this, keyword);
  if (const std::string* s = std::get_if<std::string>(&k.value)) return *s;
  wrongKeywordType(*this, k, "a string");
}

double FitsTable::number(std::string_view keyword, bool (*accepted)(double),
                         std::string_view expected) const {
  const double value = number(keyword);
  if (!accepted(value)) {
    throw IoError(where() + ": " + std::string(keyword) + " = " + formatNumber(value, "%.17g") +
                  " is not " + std::string(expected));
  }
  return value;
}

std::int64_t FitsTable::integer(std::string_view keyword, std::int64_t min,
                                std::int64_t max) const {
  const std::int64_t value = integer(keyword);
  if (value < min || value > max) {
    throw IoError(where() + ": " + std::string(keyword) + " = " + std::to_string(value) +
                  " is not an integer from " + std::to_string(min) + " to " + std::to_string(max));
  }
  return value;
}

void writeFitsTables(const std::string& path, const std::vector<FitsTable>& tables) {
  writeFitsTables(path, tables, {});
}

void writeFitsTables(const std::string& path, const std::vector<FitsTable>& tables,
                     const std::vector<std::string>& primaryCards) {
  for (const FitsTable& t : tables) validateTable(t, path);
  writeCreated(detail::createFits(path), path, tables, primaryCards);
}

std::vector<std::string> listFitsTables(const std::string& path) {
  detail::FitsPtr file = detail::openFits(path);
  return tableNames(file.get(), path);
}

FitsTable readFitsTable(const std::string& path, std::string_view hduName,
                        const std::vector<std::string>& onlyColumns) {
  detail::FitsPtr file = detail::openFits(path);
  moveToTable(file.get(), path, hduName);
  return readCurrentTable(file.get(), path, onlyColumns, {});
}

namespace {

// Moves to 0-based HDU `hduIndex`; false when there is none or it is not a BINTABLE.
bool moveToTableAt(fitsfile* f, int hduIndex) {
  int status = 0;
  int type = 0;
  if (hduIndex >= 0) fits_movabs_hdu(f, hduIndex + 1, &type, &status);
  if (hduIndex < 0 || status != 0 || type != BINARY_TBL) {
    fits_clear_errmsg();
    return false;
  }
  return true;
}

}  // namespace

bool hasFitsTableAt(const std::string& path, int hduIndex) {
  detail::FitsPtr file = detail::openFits(path);
  return moveToTableAt(file.get(), hduIndex);
}

FitsTable readFitsTableAt(const std::string& path, int hduIndex,
                          const std::vector<std::string>& onlyColumns,
                          const std::vector<std::string>& optionalColumns) {
  detail::FitsPtr file = detail::openFits(path);
  if (!moveToTableAt(file.get(), hduIndex)) {
    throw IoError(path + ": HDU " + std::to_string(hduIndex) + " is not a binary table");
  }
  // The row count sizes every column buffer: the table must fit in the file first.
  detail::requireSoundHdu(file.get(), path);
  return readCurrentTable(file.get(), path, onlyColumns, optionalColumns);
}

namespace {

ColumnType columnType(FitsColumnType t) {
  switch (t) {
    case FitsColumnType::Int16:
      return ColumnType::Int16;
    case FitsColumnType::Int32:
      return ColumnType::Int32;
    case FitsColumnType::Int64:
      return ColumnType::Int64;
    case FitsColumnType::Float32:
      return ColumnType::Float32;
    default:
      return ColumnType::Float64;
  }
}

bool numeric(FitsColumnType t) {
  return t != FitsColumnType::Unsupported && t != FitsColumnType::String;
}

}  // namespace

Table tableFromFits(const FitsTable& fits) {
  std::vector<ColumnSpec> specs;
  std::vector<const FitsColumn*> used;
  for (const FitsColumn& c : fits.columns) {
    if (!numeric(c.type()) || c.repeat != 1) continue;
    ColumnSpec spec;
    spec.name = c.name;
    spec.unit = c.unit;
    spec.description = c.comment;
    spec.type = columnType(c.type());
    specs.push_back(spec);
    used.push_back(&c);
  }
  Table out(specs);
  std::vector<std::vector<double>> values;
  for (const FitsColumn* c : used) values.push_back(fits.doubles(c->name));
  const std::int64_t rows = fits.rows();
  for (std::int64_t r = 0; r < rows; ++r) {
    double* row = out.appendRow();
    for (std::size_t c = 0; c < values.size(); ++c) row[c] = values[c][std::size_t(r)];
  }
  return out;
}

}  // namespace octarc
