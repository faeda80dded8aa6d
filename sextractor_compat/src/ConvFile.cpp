#include "octarc/sexcompat/ConvFile.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::sexcompat {

ConvKernel readConvFile(const std::string& path, std::vector<std::string>* warnings) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open convolution mask");
  std::string line;
  if (!std::getline(in, line) || line.compare(0, 4, "CONV") != 0)
    throw ConfigError(path + ":1: not a convolution mask (the first line must start with CONV)");
  // As SExtractor: "NONORM" anywhere on the line switches normalisation off, "NORM" keeps it on.
  bool normalise = true;
  if (line.find("NORM") == std::string::npos) {
    if (warnings)
      warnings->push_back(path + ":1: neither NORM nor NONORM given; the mask is normalised");
  } else {
    normalise = line.find("NONORM") == std::string::npos;
  }

  ConvKernel kernel;
  std::vector<float> values;
  int lineNo = 1;
  int firstRowLine = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    std::istringstream tokens(line);
    std::string token;
    int count = 0;
    while (tokens >> token) {
      if (count == 0 && token[0] == '#') break;
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(v))
        throw ConfigError(path + ":" + std::to_string(lineNo) + ": " + quoteForMessage(token) +
                          " is not a number");
      values.push_back(static_cast<float>(v));  // SExtractor keeps the mask in float
      ++count;
    }
    if (count == 0) continue;
    if (kernel.width == 0) {
      kernel.width = count;
      firstRowLine = lineNo;
    } else if (count != kernel.width) {
      throw ConfigError(path + ":" + std::to_string(lineNo) + ": row has " + std::to_string(count) +
                        " values but line " + std::to_string(firstRowLine) + " has " +
                        std::to_string(kernel.width));
    }
    ++kernel.height;
  }
  if (in.bad()) throw IoError(path + ": read error");
  if (values.empty())
    throw ConfigError(path + ":" + std::to_string(lineNo) + ": the mask has no values");

  double sumAbs = 0.0;
  for (float v : values) sumAbs += std::fabs(static_cast<double>(v));
  if (sumAbs == 0.0) throw ConfigError(path + ": every coefficient of the mask is zero");
  kernel.coefficients.reserve(values.size());
  for (float v : values)
    kernel.coefficients.push_back(normalise ? static_cast<float>(v / sumAbs) : v);
  return kernel;
}

}  // namespace octarc::sexcompat
