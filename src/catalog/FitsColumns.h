// Internal helpers shared by the FITS catalog writer and the column appender.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc::detail {

// Gives binary-table column `colnum` (1-based, already created by cfitsio) SExtractor's keyword
// block: TTYPEn with the description as comment, TFORMn with its repeat count, TUNITn if the unit
// is not empty, TDISPn from the printf format. The block goes right after the cards of column
// n-1 (after EXTNAME/TFIELDS for the first column).
void writeColumnCards(fitsfile* f, int colnum, const ColumnSpec& column, const std::string& path);

// The cards of a new column `colnum` (1-based) as writeColumnCards writes them: TTYPEn with the
// description as comment, TFORMn, TUNITn (unless the unit is empty), TDISPn (when the printf
// format has one).
std::vector<std::string> columnCards(int colnum, const ColumnSpec& column);

// Column number of a column keyword such as TUNIT12 ('T', upper-case letters, then digits), or 0.
int columnOfKeyword(const std::string& key);

// A stretch of consecutive row values (one or more adjacent columns) of one storage type, and
// the function that packs them.
struct PackRun {
  unsigned char* (*pack)(const double* values, int count, unsigned char* out);
  int first;  // index of the first value in Table::row()
  int count;
};

// Packs chosen columns of table rows into FITS binary-table bytes (big-endian, each column in its
// storage type, in the order given), as writeTableRows does for whole rows.
class RowPacker {
 public:
  RowPacker(const Table& table, const std::vector<int>& columns);
  // Bytes of one packed row.
  std::size_t rowBytes() const { return rowBytes_; }
  // Packs row `r` of the table at `out`; returns the end of what it wrote.
  unsigned char* pack(std::int64_t r, unsigned char* out) const;

 private:
  const Table* table_;
  std::size_t rowBytes_ = 0;  // set by the plan below: declared first
  std::vector<PackRun> runs_;
};

// Writes every row of table column `column` into FITS column `colnum`, converted to the
// column's storage type.
void writeColumnData(fitsfile* f, int colnum, const Table& table, int column,
                     const std::string& path);

// The rows of one table in the order they are written: `order` lists row indices (each once),
// or nullptr for the stored order.
struct TableRows {
  const Table* table = nullptr;
  const std::vector<std::int64_t>* order = nullptr;
  std::int64_t rows() const { return order ? std::int64_t(order->size()) : table->rows(); }
  std::int64_t rowAt(std::int64_t k) const { return order ? (*order)[std::size_t(k)] : k; }
};

// Writes the rows of `tables`, one after the other, as the rows of a binary table whose columns
// are exactly theirs (same order and types): rows are packed big-endian in memory (one tight
// loop per run of same-type columns), the next block while the previous one is written, and
// written in large blocks, far faster than column by column for big catalogs. NAXIS2 should
// already count these rows (then cfitsio writes each byte once, with no zero fill first).
void writeTableRows(fitsfile* f, const std::vector<TableRows>& tables, const std::string& path);
// Closes a file opened for writing and reports a failed close (a flush that did not reach disk).
void closeWritten(fitsfile* f, const std::string& path);

// The storage value of `value` in an integer column: rounded, clamped to the type's range, NaN
// as 0 (FITS integer columns have no NaN and SExtractor writes no TNULL).
long long integerValue(ColumnType type, double value);

bool isIntegerType(ColumnType type);

}  // namespace octarc::detail
