#include "octarc/core/Table.h"

#include <gtest/gtest.h>

namespace octarc {
namespace {

Table makeTable() {
  ColumnSpec number{"NUMBER", "Running object number", "", "meta.id", ColumnType::Int32, "%10d", 1};
  ColumnSpec vec{"VECTOR_ASSOC", "ASSOCiated parameter vector", "", "src", ColumnType::Float64,
                 "%12.7g", 3};
  ColumnSpec x{"X_IMAGE", "Object position along x", "pixel", "pos", ColumnType::Float32,
               "%11.4f", 1};
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

}  // namespace
}  // namespace octarc
