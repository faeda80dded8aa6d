// SExtractor .param files: the catalog columns a run asks for, in catalog order.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace octarc::sexcompat {

struct ParamRequest {
  std::string name;        // as written, e.g. "FLUX_APER"
  std::vector<int> sizes;  // vector sizes: (3) -> {3}, (31,31) -> {31, 31}; empty if none given
  int line = 0;            // 1-based line number in the file
};

// Reads a .param file with SExtractor's rules: leading blanks skipped, empty and '#' lines
// skipped, the name ends at a blank or at '(' '[' '{', sizes are split by blanks and , ; . ) ] }
// and end at a token starting with '#'. A repeated name is dropped (the first one is kept).
// Whether a name exists is the caller's business (SExtractor warns and skips unknown names).
// Throws IoError if the file cannot be read and ConfigError "<file>:<line>: ..." for a size that
// is not a positive integer.
std::vector<ParamRequest> readParamFile(const std::string& path);

// True when `name` (upper case, as written in a .param file) is one of SExtractor 2.25's catalog
// parameters, whether octarc measures it or not.
bool isSextractorParameter(std::string_view name);

}  // namespace octarc::sexcompat
