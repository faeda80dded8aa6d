#include "tables.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/io/FitsTable.h"

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

// numpy's code of a FITS column's type; "U" for strings.
const char* dtypeCode(FitsColumnType type) {
  switch (type) {
    case FitsColumnType::Int16:
      return "i2";
    case FitsColumnType::Int32:
      return "i4";
    case FitsColumnType::Int64:
      return "i8";
    case FitsColumnType::Float32:
      return "f4";
    case FitsColumnType::Float64:
      return "f8";
    case FitsColumnType::String:
      return "U";
    case FitsColumnType::Unsupported:
      break;
  }
  return "";
}

// A FITS column's values: numbers as a numpy array of their type (rows x repeat for a vector
// column), strings as a list.
py::object fitsColumn(const FitsTable& table, const std::string& name) {
  const FitsColumn* column = table.findColumn(name);
  if (column == nullptr) throw py::value_error("to_table: the table has no column " + name);
  return std::visit(
      [&](const auto& values) -> py::object {
        using Values = std::decay_t<decltype(values)>;
        if constexpr (std::is_same_v<Values, std::monostate>) {
          throw py::value_error("to_table: column " + name + " has an unsupported format");
        } else if constexpr (std::is_same_v<Values, std::vector<std::string>>) {
          return py::cast(values);
        } else {
          using T = typename Values::value_type;
          const std::int64_t repeat = column->repeat, rows = column->rows();
          py::array_t<T> out = repeat == 1 ? py::array_t<T>(rows) : py::array_t<T>({rows, repeat});
          std::copy(values.begin(), values.end(), out.mutable_data());
          return out;
        }
      },
      column->values);
}

}  // namespace

Table tableOf(const py::dict& columns, const std::string& what) {
  std::vector<ColumnSpec> specs;
  std::vector<py::array_t<double, py::array::c_style | py::array::forcecast>> values;
  for (const auto& [key, column] : columns) {
    const std::string name = py::str(key);
    const py::array array = py::array::ensure(column);
    if (!array || array.dtype().kind() == 'O' || array.dtype().kind() == 'U' ||
        array.dtype().kind() == 'S' || array.ndim() != 1) {
      throw py::value_error(what + ": column " + name + " is not a 1-D numeric column");
    }
    values.emplace_back(array);
    if (values.back().shape(0) != values.front().shape(0)) {
      throw py::value_error(what + ": column " + name + " has " +
                            std::to_string(values.back().shape(0)) + " rows, not " +
                            std::to_string(values.front().shape(0)));
    }
    ColumnSpec spec;
    spec.name = name;
    spec.type = ColumnType::Float64;
    specs.push_back(spec);
  }
  Table table(std::move(specs));
  const std::int64_t rows = values.empty() ? 0 : values.front().shape(0);
  for (std::int64_t r = 0; r < rows; ++r) {
    double* row = table.appendRowUnset();
    for (std::size_t c = 0; c < values.size(); ++c) row[table.offset(int(c))] = values[c].at(r);
  }
  return table;
}

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
  py::class_<FitsTable>(m, "_FitsTable", "A FITS binary table made in memory.")
      .def_property_readonly("rows", &FitsTable::rows, "Number of rows.")
      .def_property_readonly(
          "columns",
          [](const FitsTable& table) {
            py::list out;
            for (const FitsColumn& c : table.columns) {
              py::dict column;
              column["name"] = c.name;
              column["unit"] = c.unit;
              column["description"] = c.comment;
              column["dtype"] = dtypeCode(c.type());
              column["repeat"] = c.repeat;
              out.append(column);
            }
            return out;
          },
          "The columns, in order: dicts of name, unit, description, dtype (numpy code, U for "
          "text) and repeat.")
      .def_property_readonly(
          "keywords",
          [](const FitsTable& table) {
            py::list out;
            for (const FitsKeyword& k : table.keywords) {
              out.append(py::make_tuple(
                  k.name, std::visit([](const auto& v) { return py::cast(v); }, k.value),
                  k.comment));
            }
            return out;
          },
          "The header keywords, in order, as (name, value, comment).")
      .def("column", &fitsColumn, py::arg("name"),
           "The values of column `name`: a numpy array of its type, or a list of strings.");
}

}  // namespace octarc::python
