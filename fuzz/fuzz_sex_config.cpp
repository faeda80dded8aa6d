// .sex configuration files and command lines: the same input is read as a .sex file and, one
// argument per line, as an `octarc detect` command line; each valid configuration then goes
// through the run settings and the ASSOC settings, as every command reads them.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/run/RunKeys.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Assoc.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/Keys.h"

namespace {

void settingsOf(const octarc::sexcompat::Config& config) {
  try {
    octarc::settingsFromConfig(config);
  } catch (const octarc::Error&) {
  }
  try {
    octarc::sexcompat::AssocSettings::fromConfig(config);
  } catch (const octarc::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<octarc::sexcompat::KeySpec> schema = octarc::octarcKeys();
  const std::string path = octarc::fuzz::writeInput(data, size, "run.sex");
  std::vector<std::string> warnings;
  try {
    settingsOf(octarc::sexcompat::Config::load(schema, path, {}, &warnings));
  } catch (const octarc::Error&) {
  }
  std::vector<std::string> args;
  const std::string_view text = octarc::fuzz::asText(data, size);
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    args.emplace_back(text.substr(start, end - start));
    start = end + 1;
  }
  try {
    const octarc::sexcompat::CommandLine cl = octarc::sexcompat::parseCommandLine(args, schema);
    settingsOf(octarc::sexcompat::Config::load(schema, "", cl.overrides, &warnings));
  } catch (const octarc::Error&) {
  }
  return 0;
}
