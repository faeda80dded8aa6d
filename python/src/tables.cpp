#include "tables.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>

#include "octarc/core/Table.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// numpy's code of a column's storage type (the FITS writer's TFORM).
const char* dtypeCode(ColumnType type) {
  switch (type) {
    case ColumnType::Int16:
      return "i2";
    case ColumnType::Int32:
      return "i4";
    case ColumnType::Int64:
      return "i8";
    case ColumnType::Float32:
      return "f4";
    case ColumnType::Float64:
      return "f8";
  }
  return "f8";
}

// A value as a catalog file stores it in an integer column: NaN as 0, others rounded to the
// nearest integer (ties to even) and clamped to the type's range.
template <typename T>
T stored(double value) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(value);
  } else {
    if (std::isnan(value)) return 0;
    const double rounded = std::nearbyint(value);
    if (rounded <= double(std::numeric_limits<T>::min())) return std::numeric_limits<T>::min();
    if (rounded >= double(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
    return static_cast<T>(rounded);
  }
}

// The values of one column, in the type the catalog stores them in.
template <typename T>
py::array columnArray(const Table& table, int column) {
  const int repeat = table.columns()[std::size_t(column)].repeat;
  const std::int64_t rows = table.rows();
  py::array_t<T> out =
      repeat == 1 ? py::array_t<T>(rows) : py::array_t<T>({rows, std::int64_t(repeat)});
  T* values = out.mutable_data();
  for (std::int64_t r = 0; r < rows; ++r) {
    for (int e = 0; e < repeat; ++e) {
      values[r * repeat + e] = stored<T>(table.value(r, column, e));
    }
  }
  return out;
}

py::array column(const Table& table, const std::string& name) {
  const int c = table.requireColumn(name, "to_table");
  switch (table.columns()[std::size_t(c)].type) {
    case ColumnType::Int16:
      return columnArray<std::int16_t>(table, c);
    case ColumnType::Int32:
      return columnArray<std::int32_t>(table, c);
    case ColumnType::Int64:
      return columnArray<std::int64_t>(table, c);
    case ColumnType::Float32:
      return columnArray<float>(table, c);
    case ColumnType::Float64:
      return columnArray<double>(table, c);
  }
  return columnArray<double>(table, c);
}

}  // namespace

void bindTables(py::module_& m) {
  py::class_<Table>(m, "_Table", "An octarc catalog table (rows of declared columns).")
      .def_property_readonly("rows", &Table::rows, "Number of rows.")
      .def_property_readonly(
          "columns",
          [](const Table& table) {
            py::list out;
            for (const ColumnSpec& spec : table.columns()) {
              py::dict column;
              column["name"] = spec.name;
              column["unit"] = spec.unit;
              column["description"] = spec.description;
              column["ucd"] = spec.ucd;
              column["dtype"] = dtypeCode(spec.type);
              column["format"] = spec.printfFormat;
              column["repeat"] = spec.repeat;
              out.append(column);
            }
            return out;
          },
          "The declared columns, in order: dicts of name, unit, description, ucd, dtype "
          "(numpy code of the storage type), format (printf) and repeat.")
      .def("column", &column, py::arg("name"),
           "The values of column `name` as a numpy array of its storage type (rows, or rows x "
           "repeat for a vector column); ValueError for a name the table lacks.");
}

}  // namespace octarc::python
