// SExtractor's command line with Boost.Program_options: every schema key becomes a long option
// written with one dash ("-DETECT_THRESH 3"), matched case-insensitively, whose value is always
// the next argument (so "-BACK_VALUE -5" and "-ASSOCSELEC_TYPE -MATCHED" work).
#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/sexcompat/Config.h"

namespace octarc::sexcompat {

namespace po = boost::program_options;

namespace {

std::string upperCase(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return s;
}

// "--KEY" -> "-KEY", for messages in SExtractor's spelling.
std::string singleDash(std::string name) {
  while (name.size() > 1 && name[0] == '-' && name[1] == '-') name.erase(0, 1);
  if (name.empty() || name[0] != '-') name.insert(0, "-");
  return name;
}

// Boost would take an unknown "-KEY" for an image name and read "-KEY=value" as a pair; SExtractor
// users expect neither, so such arguments are refused before Boost sees them.
void rejectUnknownOptions(const std::vector<std::string>& args,
                          const std::vector<KeySpec>& schema) {
  const std::vector<std::string> flags = {"D", "DD", "DP", "H", "HELP", "V", "VERSION"};
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.size() < 2 || arg[0] != '-') continue;
    std::string name = upperCase(arg.substr(arg[1] == '-' ? 2 : 1));
    const std::size_t eq = name.find('=');
    if (eq != std::string::npos)
      throw ConfigError("command line: " + quoteForMessage(arg.substr(0, arg.find('='))) +
                        ": write -KEY value as two arguments (no '=')");
    if (name == "C") {
      ++i;  // the file name
      continue;
    }
    if (std::find(flags.begin(), flags.end(), name) != flags.end()) continue;
    const bool known =
        std::any_of(schema.begin(), schema.end(), [&](const KeySpec& k) { return k.name == name; });
    if (!known) {
      const std::string nearest = nearestKey(schema, name);
      throw ConfigError("command line: " + quoteForMessage(arg) + ": unknown keyword" +
                        (nearest.empty() ? "" : " (did you mean -" + nearest + "?)"));
    }
    if (arg[1] == '-')
      throw ConfigError("command line: " + quoteForMessage(arg) +
                        ": keys take one dash, as in SExtractor (-" + name + ")");
    ++i;  // its value, which may start with '-'
  }
}

}  // namespace

CommandLine parseCommandLine(const std::vector<std::string>& args,
                             const std::vector<KeySpec>& schema) {
  po::options_description options;
  // clang-format off
  options.add_options()
      ("c", po::value<std::string>(), "configuration file")
      ("d", "dump the default configuration")
      ("dd", "dump the full configuration")
      ("dp", "dump the catalog parameters")
      ("h", "help")
      ("help", "help")
      ("v", "version")
      ("version", "version");
  // clang-format on
  for (const auto& spec : schema)
    options.add_options()(spec.name.c_str(), po::value<std::string>());
  options.add_options()("positional-input", po::value<std::vector<std::string>>());
  po::positional_options_description positional;
  positional.add("positional-input", -1);

  // No guessing: "-DETECT" must not silently mean DETECT_THRESH. No "-KEY=value" either:
  // SExtractor does not support it, so it is refused rather than read differently.
  const int style =
      po::command_line_style::allow_long | po::command_line_style::allow_long_disguise |
      po::command_line_style::long_allow_next | po::command_line_style::long_case_insensitive;

  rejectUnknownOptions(args, schema);
  po::parsed_options parsed(&options);
  try {
    parsed =
        po::command_line_parser(args).options(options).positional(positional).style(style).run();
  } catch (const po::unknown_option& e) {
    throw ConfigError("command line: " + singleDash(e.get_option_name()) + ": unknown keyword");
  } catch (const po::invalid_command_line_syntax& e) {
    if (e.kind() == po::invalid_command_line_syntax::long_adjacent_not_allowed)
      throw ConfigError("command line: " + singleDash(e.get_option_name()) +
                        ": write -KEY value as two arguments (no '=')");
    throw ConfigError("command line: " + singleDash(e.get_option_name()) + ": missing value");
  } catch (const po::error& e) {
    throw ConfigError(std::string("command line: ") + e.what());
  }

  CommandLine result;
  for (const auto& opt : parsed.options) {
    std::string key = opt.string_key;
    if (key == "positional-input") {
      result.positional.insert(result.positional.end(), opt.value.begin(), opt.value.end());
      continue;
    }
    std::string lower;
    for (char ch : key) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (lower == "c") {
      if (opt.value.empty()) throw ConfigError("command line: -c: missing file name");
      result.configFile = opt.value.front();
    } else if (lower == "d") {
      result.dumpConfig = true;
    } else if (lower == "dd") {
      result.dumpConfigFull = true;
    } else if (lower == "dp") {
      result.dumpParams = true;
    } else if (lower == "h" || lower == "help") {
      result.help = true;
    } else if (lower == "v" || lower == "version") {
      result.version = true;
    } else {
      const std::string upperKey = upperCase(key);
      if (opt.value.empty()) throw ConfigError("command line: -" + upperKey + ": missing value");
      result.overrides.emplace_back(upperKey, opt.value.front());
    }
  }
  return result;
}

}  // namespace octarc::sexcompat
