#include "octarc/app/Options.h"

#include <algorithm>
#include <cctype>
#include <map>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc {

namespace po = boost::program_options;

namespace {

bool isSwitch(const po::option_description& d) {
  return d.semantic()->max_tokens() == 0;
}

// Boost's "arg (=0.257)" -> "0.257"; "" without a default.
std::string defaultText(const po::option_description& d) {
  const std::string text = d.format_parameter();
  const std::size_t open = text.find("(=");
  if (open == std::string::npos || text.back() != ')') return "";
  return text.substr(open + 2, text.size() - open - 3);
}

// Y or N (also T/F, YES/NO, TRUE/FALSE, 1/0, any case) of a switch given as a key.
bool switchValue(const std::string& key, const std::string& value) {
  std::string v;
  for (const char c : value) v += char(std::toupper(static_cast<unsigned char>(c)));
  if (v == "Y" || v == "T" || v == "YES" || v == "TRUE" || v == "1") return true;
  if (v == "N" || v == "F" || v == "NO" || v == "FALSE" || v == "0") return false;
  throw ConfigError("command line: -" + key + ": expected Y or N, got " + quoteForMessage(value));
}

// The long and short options of `args` written as `-KEY value`, so that one parse reads them.
std::vector<std::string> optionsAsKeys(const std::vector<std::string>& args,
                                       const po::options_description& options) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const po::option_description* d = nullptr;
    std::optional<std::string> glued;
    if (a.rfind("--", 0) == 0 && a.size() > 2) {
      const std::size_t eq = a.find('=');
      d = options.find_nothrow(a.substr(2, eq == std::string::npos ? eq : eq - 2), false, false,
                               false);
      if (eq != std::string::npos) glued = a.substr(eq + 1);
    } else if (a.size() == 2 && a[0] == '-' && a[1] != '-') {
      d = options.find_nothrow(a, false, false, false);  // Boost keeps short names as "-n"
    }
    if (!d || d->long_name() == "help") {
      out.push_back(a);
      continue;
    }
    out.push_back("-" + optionKey(d->long_name()));
    if (glued) {
      out.push_back(*glued);
    } else if (isSwitch(*d)) {
      out.push_back("Y");
    } else if (i + 1 < args.size()) {
      out.push_back(args[++i]);
    }
  }
  return out;
}

}  // namespace

std::string optionKey(const std::string& longName) {
  std::string key;
  for (const char c : longName) {
    key += c == '-' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
  }
  return key;
}

std::vector<sexcompat::KeySpec> optionKeys(const po::options_description& options) {
  std::vector<sexcompat::KeySpec> keys;
  for (const auto& d : options.options()) {
    if (d->long_name() == "help") continue;
    sexcompat::KeySpec k;
    k.name = optionKey(d->long_name());
    k.kind = isSwitch(*d) ? sexcompat::KeySpec::Kind::Bool : sexcompat::KeySpec::Kind::String;
    k.minCount = 0;
    k.maxCount = 64;  // "MEAN,SCATTER" and other lists pass whole to the option
    const std::string value = isSwitch(*d) ? "N" : defaultText(*d);
    if (!value.empty()) k.defaults = {value};
    k.comment = d->description();
    keys.push_back(k);
  }
  return keys;
}

std::optional<ParsedOptions> parseOptions(const std::vector<std::string>& args,
                                          const CommandSpec& command,
                                          const po::options_description& options,
                                          std::size_t maxPositional) {
  const std::optional<sexcompat::CommandLine> cl =
      parseArguments(optionsAsKeys(args, options), command, optionKeys(options));
  if (!cl) return std::nullopt;
  const std::string seeHelp = " (see octarc " + command.name + " -h)";
  if (cl->positional.size() > maxPositional) {
    throw ConfigError("command line: " + quoteForMessage(cl->positional[maxPositional]) +
                      ": unexpected argument" + seeHelp);
  }
  // The last value of each key, as Boost long options: those of a -c file (as -d writes it: a
  // key without a value is not given), then those of the command line.
  std::map<std::string, std::string> last;
  if (!cl->configFile.empty()) {
    const std::vector<sexcompat::KeySpec> keys = optionKeys(options);
    std::vector<std::string> warnings;
    const sexcompat::Config file = sexcompat::Config::load(keys, cl->configFile, {}, &warnings);
    for (const sexcompat::KeySpec& k : keys) {
      if (!file.isExplicit(k.name) || file.givenWithoutValue(k.name)) continue;
      std::string joined;
      for (const std::string& v : file.getStrings(k.name)) {
        joined += (joined.empty() ? "" : ",") + v;
      }
      last[k.name] = joined;
    }
  }
  for (const auto& [key, value] : cl->overrides) last[key] = value;
  std::vector<std::string> tokens;
  for (const auto& d : options.options()) {
    const auto it = last.find(optionKey(d->long_name()));
    if (it == last.end()) continue;
    if (!isSwitch(*d)) {
      tokens.push_back("--" + d->long_name() + "=" + it->second);
    } else if (switchValue(it->first, it->second)) {
      tokens.push_back("--" + d->long_name());
    }
  }
  ParsedOptions out;
  try {
    po::store(po::command_line_parser(tokens).options(options).run(), out.values);
    po::notify(out.values);
  } catch (const po::error& e) {
    throw ConfigError("command line: " + std::string(e.what()) + seeHelp);
  }
  out.positional = cl->positional;
  return out;
}

}  // namespace octarc
