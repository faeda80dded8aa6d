// SExtractor .conv files (FILTER_NAME): detection convolution masks.
#pragma once

#include <string>
#include <vector>

#include "octarc/core/ConvKernel.h"

namespace octarc::sexcompat {

// Reads a .conv file with SExtractor's rules. Line 1 starts with "CONV"; "NORM" on it divides the
// mask by the sum of |k|, "NONORM" keeps it raw, neither normalises and adds a warning. Then one
// row of whitespace-separated numbers per line; blank lines and lines whose first token starts
// with '#' are skipped. Throws IoError if the file cannot be read and ConfigError
// "<file>:<line>: ..." for a missing CONV line, a non-number, rows of different lengths, an empty
// or an all-zero mask. `warnings` may be null.
ConvKernel readConvFile(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace octarc::sexcompat
