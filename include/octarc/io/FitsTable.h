// Generic FITS binary tables: files of one or more named BINTABLE HDUs with typed columns and
// header keywords, written and read back by HDU name and column name (cfitsio stays inside
// src/io).
//
// Column types and their TFORM codes: Int16 'I', Int32 'J', Int64 'K', Float32 'E', Float64 'D'
// (each optionally a fixed-length vector, TFORM "rX"), and fixed-width strings 'wA' (one string
// per row; trailing blanks are not significant and are stripped on reading). Numeric values are
// stored row-major: row r of a column with repeat n holds values[r * n .. r * n + n). NaN is
// written as IEEE NaN in float columns (no TNULL).
//
// Keywords: logical, signed or unsigned integer, real and string values, each with a comment.
// A real NaN is written as an undefined value (an empty value field) and read back as NaN;
// strings longer than one card use the CONTINUE long-string convention (with the LONGSTRN
// keyword). Reals are written in the shortest form that reads back to the same double.
//
// On reading, TSCAL/TZERO are applied by cfitsio; unsigned columns (TZERO 32768, 2^31) come
// back in the next wider signed type, 'B' (byte) columns as Int16. Columns of other formats
// (logical, bit, complex, variable-length, string vectors) are listed with empty values, and
// asking for their values is an IoError naming the format.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "octarc/core/Table.h"

namespace octarc {

enum class FitsColumnType { Unsupported, Int16, Int32, Int64, Float32, Float64, String };

// Name used in messages ("int32", "float64", "string"...).
std::string_view fitsColumnTypeName(FitsColumnType type);

// The values of a column; std::monostate for a column read in an unsupported format.
using FitsColumnValues =
    std::variant<std::monostate, std::vector<std::int16_t>, std::vector<std::int32_t>,
                 std::vector<std::int64_t>, std::vector<float>, std::vector<double>,
                 std::vector<std::string>>;

struct FitsColumn {
  std::string name;     // TTYPEn
  std::string comment;  // comment of the TTYPEn card (the column's description)
  std::string unit;     // TUNITn, "" for none
  std::string display;  // TDISPn, a Fortran display format such as "F8.4"; "" for none
  // Numeric columns: elements per row (a vector column when > 1). String columns: the width in
  // characters; 0 when writing means the longest value's length (at least 1).
  int repeat = 1;
  FitsColumnValues values;
  std::string tform;       // filled when read (e.g. "3J", "16A"); ignored when writing
  std::string dimensions;  // TDIMn, e.g. "(80, 36)" for an LDAC header cell; "" for none

  FitsColumnType type() const;
  // Rows held: values / repeat for numeric columns, the number of strings for string ones.
  std::int64_t rows() const;
};

using FitsKeywordValue = std::variant<bool, std::int64_t, std::uint64_t, double, std::string>;

struct FitsKeyword {
  std::string name;  // at most 8 characters of A-Z, 0-9, '-', '_'
  FitsKeywordValue value;
  std::string comment;

  static FitsKeyword logical(std::string name, bool value, std::string comment = "");
  static FitsKeyword integer(std::string name, std::int64_t value, std::string comment = "");
  static FitsKeyword unsignedInteger(std::string name, std::uint64_t value,
                                     std::string comment = "");
  static FitsKeyword real(std::string name, double value, std::string comment = "");
  static FitsKeyword text(std::string name, std::string value, std::string comment = "");
};

// One BINTABLE HDU. When read from a file, `source` is that file's path; accessors throw
// IoError("<source>[<name>]: ...") naming the HDU and the column or keyword concerned.
struct FitsTable {
  std::string name;                   // EXTNAME
  std::vector<FitsKeyword> keywords;  // in header order, without the structural ones
  std::vector<FitsColumn> columns;
  std::string source;

  // Rows of the table (of its first column; 0 without columns).
  std::int64_t rows() const;

  // The column of that name: an exact match, else the only case-insensitive one (FITS column
  // names are case-insensitive). nullptr / IoError when there is none.
  const FitsColumn* findColumn(std::string_view columnName) const;
  const FitsColumn& column(std::string_view columnName) const;
  // Values of a column that must hold `repeat` elements per row (0: any). doubles() takes any
  // numeric column (integers converted), integers() only integer columns, strings() only
  // string columns; IoError for a missing column, the wrong type or the wrong repeat.
  std::vector<double> doubles(std::string_view columnName, int repeat = 1) const;
  std::vector<std::int64_t> integers(std::string_view columnName, int repeat = 1) const;
  std::vector<std::string> strings(std::string_view columnName) const;

  // Keywords by name (case-insensitive, as in FITS); the first one of that name.
  const FitsKeyword* findKeyword(std::string_view keyword) const;
  bool hasKeyword(std::string_view keyword) const { return findKeyword(keyword) != nullptr; }
  // Typed keyword values; IoError when the keyword is missing or of another type. number()
  // takes integer and real values, unsignedInteger() non-negative integers.
  double number(std::string_view keyword) const;
  std::int64_t integer(std::string_view keyword) const;
  std::uint64_t unsignedInteger(std::string_view keyword) const;
  bool logical(std::string_view keyword) const;
  std::string text(std::string_view keyword) const;
  // The same with the value range-checked: IoError "<where>: KEY = value is not <expected>"
  // when `accepted` refuses the number (expected e.g. "a finite number > 0"), or when the
  // integer lies outside [min, max].
  double number(std::string_view keyword, bool (*accepted)(double),
                std::string_view expected) const;
  std::int64_t integer(std::string_view keyword, std::int64_t min, std::int64_t max) const;

  // "<source>[<name>]", or "[<name>]" for a table made in memory.
  std::string where() const;
};

// Writes a new FITS file at `path` (which must not exist: pass the temporary path of an
// AtomicFile / OutputFiles entry): an empty primary HDU and one BINTABLE extension per table,
// in order. Every column of a table must hold the same number of rows. Throws IoError naming
// the file, the HDU and the column or keyword at fault (empty or repeated names, values that do
// not fill whole rows, strings longer than their width, infinite keyword values, ...); the
// partly written file is removed.
void writeFitsTables(const std::string& path, const std::vector<FitsTable>& tables);
// The same, with `primaryCards` (whole header cards of at most 80 characters, such as HISTORY
// records) written verbatim into the primary header after its structural keywords.
void writeFitsTables(const std::string& path, const std::vector<FitsTable>& tables,
                     const std::vector<std::string>& primaryCards);

// EXTNAMEs of the file's BINTABLE HDUs, in file order ("" for one without EXTNAME).
std::vector<std::string> listFitsTables(const std::string& path);

// Reads the BINTABLE HDU named `hduName` (EXTNAME, case-insensitive): its keywords, and its
// columns with their values (every column, or only those named in `onlyColumns`, each of which
// must exist). IoError naming the file when it cannot be read, has no such table (the tables
// it has are listed), or is shorter than its table's rows.
FitsTable readFitsTable(const std::string& path, std::string_view hduName,
                        const std::vector<std::string>& onlyColumns = {});

// True when the file has a BINTABLE at 0-based HDU index `hduIndex` (1: the first extension);
// IoError when the file cannot be opened.
bool hasFitsTableAt(const std::string& path, int hduIndex);

// Reads the BINTABLE at 0-based HDU index `hduIndex`, whatever its EXTNAME, as readFitsTable
// does, after checking that the HDU's stated data size fits in the file. The columns named in
// `optionalColumns` are read as well when the table has them; with both lists empty, every
// column is read. IoError naming the file when that HDU is missing or not a BINTABLE.
FitsTable readFitsTableAt(const std::string& path, int hduIndex,
                          const std::vector<std::string>& onlyColumns = {},
                          const std::vector<std::string>& optionalColumns = {});

// A table's scalar numeric columns as a core Table (values as double, types and units kept);
// vector and string columns are left out.
Table tableFromFits(const FitsTable& table);

}  // namespace octarc
