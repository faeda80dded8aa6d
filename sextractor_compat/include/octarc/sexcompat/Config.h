// SExtractor-style configuration: .sex files, `-KEY value` command-line overrides and the
// `-d`/`-dd` dumps. The semantics follow SExtractor 2.25 (see docs SEXTRACTOR.md §7):
// internal defaults, then the configuration file, then the command line; the last value wins.
#pragma once

#include <limits>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace octarc::sexcompat {

// One configuration key, as a row of a key table (the role of SExtractor's preflist.h).
struct KeySpec {
  enum class Kind { Bool, Int, Float, String, Keyword };

  std::string name;  // upper case, e.g. "DETECT_THRESH"
  Kind kind = Kind::String;
  int minCount = 1, maxCount = 1;  // allowed number of values (comma lists); 0 = may be empty
  double minValue = -std::numeric_limits<double>::max();  // numeric range, inclusive
  double maxValue = std::numeric_limits<double>::max();
  std::vector<std::string> keywords;  // allowed values of a Keyword key, upper case
  std::vector<std::string> defaults;  // default value(s) as text
  std::string comment;                // for the dumps; '\n' starts a continuation line
  bool expertOnly = false;            // listed only by the full dump (-dd)
  // A muparser expression (or a list of them): its text is kept as written, '=', ';' and blanks
  // included, and a list splits only at commas outside parentheses ("min(A, B), C" is two
  // values); '"' quotes are dropped and '#' starts a comment, in .sex files and on the command
  // line alike. Other keys split at SExtractor's separators (blank, tab, '=', ',', ';', '"').
  bool expression = false;
  // A key SExtractor has and octarc accepts but does not act on: its comment says "(ignored by
  // octarc)", and setting it (on the command line, or in a file to another value than its
  // default) draws a warning from Config::load.
  bool ignored = false;
};

// Where Config::where() says a key given on a command line was set.
inline constexpr const char* kCommandLine = "command line";

// A validated set of configuration values, one entry per key of the schema it was loaded with.
class Config {
 public:
  // Reads the defaults of `schema`, then `sexFile` (skipped when empty), then `overrides`
  // (KEY, value pairs from the command line, in order). Keys are case-insensitive.
  // Throws ConfigError for a file that cannot be read, a malformed value (naming key, value and
  // file:line or "command line"), a value holding a control character (NUL, ESC, ...; shown
  // escaped) or an unknown key on the command line. Unknown keys in the file are skipped with a
  // message appended to `warnings` (may be null). A key given with an empty list, where the key
  // allows one (a bare "WEIGHT_TYPE" line, "WEIGHT_THRESH ,"), counts as not given, as in
  // SExtractor: it keeps its value (the default unless set before) and is not explicit.
  // A key marked ignored (KeySpec::ignored) that is set on the command line, or in the file to
  // another value than its default (a template lists every key), adds one warning to `warnings`
  // naming where it was set: the setting has no effect.
  // `origin` is how messages name where the overrides come from: a command line's "-KEY" by
  // default; a program embedding octarc names its own (e.g. Python's config= dict, "KEY").
  struct OverrideOrigin {
    std::string name = kCommandLine;
    std::string keyPrefix = "-";
  };
  static Config load(const std::vector<KeySpec>& schema, const std::string& sexFile,
                     const std::vector<std::pair<std::string, std::string>>& overrides,
                     std::vector<std::string>* warnings, const OverrideOrigin& origin);
  static Config load(const std::vector<KeySpec>& schema, const std::string& sexFile,
                     const std::vector<std::pair<std::string, std::string>>& overrides,
                     std::vector<std::string>* warnings) {
    return load(schema, sexFile, overrides, warnings, OverrideOrigin());
  }

  // Typed access; `i` is the index in a comma list. Throws ConfigError for a key that is not in
  // the schema, a value of another kind, or an index past the end of the list.
  bool getBool(std::string_view key, int i = 0) const;
  int getInt(std::string_view key, int i = 0) const;
  double getDouble(std::string_view key, int i = 0) const;       // Int or Float keys
  std::string getString(std::string_view key, int i = 0) const;  // any kind, canonical text
  std::vector<int> getInts(std::string_view key) const;
  std::vector<double> getDoubles(std::string_view key) const;
  std::vector<std::string> getStrings(std::string_view key) const;
  int count(std::string_view key) const;  // number of values in the list
  bool has(std::string_view key) const;   // key is part of the schema
  // True when the value came from the configuration file or the command line.
  bool isExplicit(std::string_view key) const;
  // Where the value was last set: "file:line" or "command line"; "" for the default.
  std::string where(std::string_view key) const;
  // True when the key was last given as a list of no value with a comma in it ("COLOUR_CUT ,"),
  // which counts as not given (as in SExtractor), so that a key may refuse it.
  bool givenWithoutValue(std::string_view key) const;
  // The keys whose value has been asked for so far (upper case): what a run actually uses, so
  // that a test can check that no key marked "(ignored by octarc)" is read.
  std::set<std::string> keysRead() const { return read_; }

  // The current values as a .sex file (SExtractor's -d / -dd layout). `full` also lists the
  // expert keys. The text loads back through load() with the same schema.
  std::string dump(const std::vector<KeySpec>& schema, bool full) const;

 private:
  struct Value {
    KeySpec::Kind kind = KeySpec::Kind::String;
    std::vector<std::string> text;  // canonical text: keywords upper case, booleans "Y"/"N"
    bool isExplicit = false;
    bool givenWithoutValue = false;
    std::string where;  // where the value was last set: "file:line" or "command line"
  };
  const Value& find(std::string_view key) const;
  static void setValue(Value& v, const KeySpec& spec, const std::vector<std::string>& raw,
                       std::string_view text, const std::string& where);
  std::map<std::string, Value, std::less<>> values_;
  mutable std::set<std::string> read_;
};

// The key of `schema` nearest to `name` (case-insensitive edit distance), for a "did you mean"
// hint; "" when none is close (at most 2 edits, and fewer than a third of the name's length).
std::string nearestKey(const std::vector<KeySpec>& schema, std::string_view name);

// What the command line asked for. `-c`, `-d`, `-dd`, `-dp`, `-h`/`--help`, `-v`/`--version`
// are options; every other `-KEY` takes the next argument as its value (SExtractor style).
struct CommandLine {
  std::vector<std::string> positional;                         // image names
  std::string configFile;                                      // "" if no -c
  std::vector<std::pair<std::string, std::string>> overrides;  // (KEY upper case, value), in order
  bool dumpConfig = false, dumpConfigFull = false, dumpParams = false;
  bool help = false, version = false;
};

// Parses argv[1..] (without the program name). Throws ConfigError naming the argument for an
// unknown `-KEY` (with the nearest key as a hint), a missing value, the unsupported
// `-KEY=value` form or a key written with two dashes (`--KEY`).
CommandLine parseCommandLine(const std::vector<std::string>& args,
                             const std::vector<KeySpec>& schema);

}  // namespace octarc::sexcompat
