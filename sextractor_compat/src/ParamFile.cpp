#include "octarc/sexcompat/ParamFile.h"

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <fstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::sexcompat {

std::vector<ParamRequest> readParamFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open parameter file");
  std::vector<ParamRequest> requests;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    const std::size_t nameEnd = line.find_first_of(" \t\r([{#", start);
    ParamRequest request;
    request.name =
        line.substr(start, nameEnd == std::string::npos ? std::string::npos : nameEnd - start);
    request.line = lineNo;
    if (nameEnd != std::string::npos) {
      const std::string rest = line.substr(nameEnd);
      constexpr const char* kSizeSeparators = " \t\r,;.([{)]}";
      std::size_t pos = 0;
      long elements = 1;
      while ((pos = rest.find_first_not_of(kSizeSeparators, pos)) != std::string::npos) {
        const std::size_t end = rest.find_first_of(kSizeSeparators, pos);
        const std::string token =
            rest.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
        if (token[0] == '#') break;
        errno = 0;
        char* tail = nullptr;
        const long size = std::strtol(token.c_str(), &tail, 10);
        const std::string where =
            path + ":" + std::to_string(lineNo) + ": " + quoteForMessage(request.name);
        if (tail == token.c_str() || *tail != '\0' || errno == ERANGE || size > INT_MAX)
          throw ConfigError(where + ": vector size " + quoteForMessage(token) +
                            " is not an integer");
        if (size <= 0)
          throw ConfigError(where + ": vector size must be positive, got " +
                            quoteForMessage(token));
        // The column holds the product of the sizes: it must be an int, like each size.
        if (elements > INT_MAX / size)
          throw ConfigError(where + ": vector of more than " + std::to_string(INT_MAX) +
                            " elements");
        elements *= size;
        request.sizes.push_back(static_cast<int>(size));
        pos = end;
      }
    }
    bool duplicate = false;
    for (const auto& r : requests) duplicate = duplicate || r.name == request.name;
    if (!duplicate) requests.push_back(std::move(request));
  }
  if (in.bad()) throw IoError(path + ": read error");
  return requests;
}

}  // namespace octarc::sexcompat
