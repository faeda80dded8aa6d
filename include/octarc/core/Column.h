// Declaration of one catalog column: what SExtractor keeps in a param.h row.
#pragma once

#include <string>
#include <vector>

namespace octarc {

// Storage type in FITS tables (TFORM code in brackets).
enum class ColumnType {
  Int16,    // I
  Int32,    // J
  Int64,    // K
  Float32,  // E
  Float64,  // D
};

struct ColumnSpec {
  std::string name;         // catalog name, e.g. "X_IMAGE"
  std::string description;  // one line, goes into the TTYPE comment
  std::string unit;         // SExtractor unit string ("pixel", "pixel**2", "deg", "count"), or ""
  std::string ucd;          // IVOA UCD, e.g. "pos.cartesian.x;instr.det"
  ColumnType type = ColumnType::Float32;
  std::string printfFormat;  // e.g. "%11.4f": ASCII output and TDISP
  int repeat = 1;            // vector size (VECTOR_ASSOC(n)); 1 for scalars
};

// A value of a floating-point column as the catalog stores it: rounded to float in a Float32
// column (what a reader of the file gets back), unchanged otherwise.
inline double storedFloatValue(ColumnType type, double value) {
  return type == ColumnType::Float32 ? double(float(value)) : value;
}

}  // namespace octarc
