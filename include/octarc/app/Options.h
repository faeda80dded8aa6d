// The commands that take GNU-style long options (simulate, demo) on the one parse of every
// command (CommandLine.h): each option is also the configuration key of its name in capitals.
#pragma once

#include <boost/program_options.hpp>
#include <optional>
#include <string>
#include <vector>

#include "octarc/app/CommandLine.h"

namespace octarc {

// An option value stored into `target` when the option is given (at po::notify), left unset
// otherwise: the settings structs keep "not given" apart from any default.
template <typename T>
boost::program_options::typed_value<T>* optionalValue(std::optional<T>& target) {
  return boost::program_options::value<T>()->notifier([&target](const T& v) { target = v; });
}

// The -h text's paragraph on the two spellings of these commands' options.
inline constexpr const char* kOptionsAsKeys =
    "Every option is also a configuration key, in SExtractor's style: --pixel-scale 0.3 is\n"
    "-PIXEL_SCALE 0.3, a switch such as --quiet is -QUIET Y (or N), and the last value of a\n"
    "key wins. -d and -dd list the keys with their defaults as a .sex file, which -c FILE\n"
    "reads back (the command line's keys over the file's), -dp the columns of the catalog\n"
    "written (an error when none is), -v the version.\n";

// The configuration key of a long option: "pixel-scale" -> "PIXEL_SCALE".
std::string optionKey(const std::string& longName);

// The keys of `options` (but help) for parseArguments and the -d dump: a switch is a Y/N key
// (default N), an option with a value a text key with Boost's default as its default.
std::vector<sexcompat::KeySpec> optionKeys(
    const boost::program_options::options_description& options);

struct ParsedOptions {
  boost::program_options::variables_map values;  // stored and notified
  std::vector<std::string> positional;
};

// Parses the arguments of a command with long options: `-KEY value` (KEY = optionKey of the
// long name; a switch takes Y or N), `--name value`, `--name=value`, the short names and a bare
// switch are the same; the last value of a key wins, as in SExtractor. The flags (-h, -v, -d,
// -dd, -dp) are acted on as for every command (nullopt). At most `maxPositional` positional
// arguments. ConfigError naming the option for an unknown option, a bad value, a -c file (these
// commands have no configuration file of their own keys).
std::optional<ParsedOptions> parseOptions(
    const std::vector<std::string>& args, const CommandSpec& command,
    const boost::program_options::options_description& options, std::size_t maxPositional = 0);

}  // namespace octarc
