#include "octarc/core/Table.h"

#include <gtest/gtest.h>

namespace octarc {
namespace {

Table makeTable() {
  ColumnSpec number{"NUMBER", "Running object number", "", "meta.id", ColumnType::Int32, "%10d", 1};
  ColumnSpec vec{
      "VECTOR_ASSOC", "ASSOCiated parameter vector", "", "src", ColumnType::Float64, "%12.7g", 3};
  ColumnSpec x{"X_IMAGE", "Object position along x", "pixel", "pos", ColumnType::Float32, "%11.4f",
               1};
  return Table({number, vec, x});
}

TEST(Table, LayoutFollowsRepeatCounts) {
  Table t = makeTable();
  EXPECT_EQ(t.rowWidth(), 5);
  EXPECT_EQ(t.offset(0), 0);
  EXPECT_EQ(t.offset(1), 1);
  EXPECT_EQ(t.offset(2), 4);
  EXPECT_EQ(t.findColumn("X_IMAGE"), 2);
  EXPECT_EQ(t.findColumn("x_image"), -1);
}

TEST(Table, AppendSetAndFilterRows) {
  Table t = makeTable();
  for (int i = 1; i <= 4; ++i) {
    double* row = t.appendRow();
    row[0] = i;
    row[4] = 10.5 * i;
  }
  t.setValue(2, 1, 7.0, 2);
  EXPECT_EQ(t.rows(), 4);
  EXPECT_DOUBLE_EQ(t.value(2, 1, 2), 7.0);
  t.filterRows({true, false, true, false});
  ASSERT_EQ(t.rows(), 2);
  EXPECT_DOUBLE_EQ(t.value(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(t.value(1, 0), 3.0);
  EXPECT_DOUBLE_EQ(t.value(1, 2), 31.5);
  EXPECT_DOUBLE_EQ(t.value(1, 1, 2), 7.0);
}

TEST(Table, ManyRowsAcrossChunksKeepTheirValuesAndPointers) {
  Table t = makeTable();
  std::vector<double*> first;
  for (int i = 0; i < 10000; ++i) {
    double* row = t.appendRow();
    EXPECT_EQ(row[4], 0.0);  // new rows are zero-filled
    row[0] = i;
    row[4] = 0.5 * i;
    if (i < 3) first.push_back(row);
  }
  ASSERT_EQ(t.rows(), 10000);
  EXPECT_EQ(first[2], t.row(2));  // growing never moves a row
  EXPECT_DOUBLE_EQ(t.value(9999, 2), 0.5 * 9999);
  std::vector<bool> keep(10000);
  for (int i = 0; i < 10000; ++i) keep[std::size_t(i)] = i % 3 == 0;
  t.filterRows(keep);
  ASSERT_EQ(t.rows(), 3334);
  EXPECT_DOUBLE_EQ(t.value(3333, 0), 9999.0);
  EXPECT_DOUBLE_EQ(t.value(1000, 2), 0.5 * 3000);
  double* again = t.appendRow();
  EXPECT_EQ(again[0], 0.0);
  EXPECT_EQ(again[4], 0.0);
}

TEST(Table, UnsetRowsAreWrittenByTheCallerAndZeroRowsStayZero) {
  Table t = makeTable();
  for (int i = 0; i < 3000; ++i) {
    double* row = t.appendRowUnset();
    for (int c = 0; c < t.rowWidth(); ++c) row[c] = i + 0.25 * c;
  }
  double* zero = t.appendRow();  // a zero-filled row after unset ones, in a used chunk
  for (int c = 0; c < t.rowWidth(); ++c) EXPECT_EQ(zero[c], 0.0) << c;
  ASSERT_EQ(t.rows(), 3001);
  EXPECT_DOUBLE_EQ(t.value(2999, 0), 2999.0);
  EXPECT_DOUBLE_EQ(t.row(1234)[t.rowWidth() - 1], 1234 + 0.25 * (t.rowWidth() - 1));
}

TEST(Table, LargeChunksHoldManyRowsLikeSmallOnes) {
  // 1.2 million values per column set: more than one large chunk for this row width.
  Table big(makeTable().columns(), Table::Chunks::Large);
  Table small(makeTable().columns());
  std::vector<double*> rows;
  for (int i = 0; i < 300000; ++i) {
    double* a = big.appendRowUnset();
    double* b = small.appendRow();
    for (int c = 0; c < big.rowWidth(); ++c) a[c] = b[c] = i * 10.0 + c;
    if (i % 65536 == 0) rows.push_back(a);
  }
  ASSERT_EQ(big.rows(), small.rows());
  for (std::int64_t r = 0; r < big.rows(); r += 997) {
    for (int c = 0; c < big.rowWidth(); ++c) ASSERT_EQ(big.row(r)[c], small.row(r)[c]);
  }
  for (std::size_t k = 0; k < rows.size(); ++k)
    EXPECT_EQ(rows[k], big.row(std::int64_t(k) * 65536));
  std::vector<bool> keep(300000);
  for (std::size_t i = 0; i < keep.size(); ++i) keep[i] = i % 7 == 3;
  big.filterRows(keep);
  ASSERT_EQ(big.rows(), 42857);
  EXPECT_EQ(big.value(42856, 0), 299995 * 10.0);
  EXPECT_EQ(big.appendRow()[1], 0.0);
}

}  // namespace
}  // namespace octarc
