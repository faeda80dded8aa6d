#include "octarc/sexcompat/Config.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::sexcompat {
namespace {

// SExtractor's token separators in .sex lines (prefs.c): blank, tab, '=', ',', ';', '"'.
constexpr std::string_view kSeparators = " \t=,;\"\r\n";

std::vector<std::string> tokenize(std::string_view line) {
  std::vector<std::string> tokens;
  std::size_t pos = 0;
  while (true) {
    pos = line.find_first_not_of(kSeparators, pos);
    if (pos == std::string_view::npos) break;
    std::size_t end = line.find_first_of(kSeparators, pos);
    if (end == std::string_view::npos) end = line.size();
    tokens.emplace_back(line.substr(pos, end - pos));
    pos = end;
  }
  return tokens;
}

// The value of an expression key (KeySpec::expression), kept as written: '=', ';' and blanks
// stay. '#' starts a comment, '"' quotes, tabs and line ends count as blanks; a list splits
// only at commas outside parentheses, and each value is trimmed (empty ones are dropped).
std::vector<std::string> tokenizeExpression(std::string_view text) {
  std::vector<std::string> values;
  std::string current;
  int depth = 0;
  auto flush = [&] {
    const std::size_t first = current.find_first_not_of(' ');
    if (first != std::string::npos)
      values.push_back(current.substr(first, current.find_last_not_of(' ') - first + 1));
    current.clear();
  };
  for (char c : text) {
    if (c == '#') break;
    if (c == '"' || c == '\t' || c == '\r' || c == '\n') c = ' ';
    if (c == '(') {
      ++depth;
    } else if (c == ')') {
      depth = std::max(0, depth - 1);
    } else if (c == ',' && depth == 0) {
      flush();
      continue;
    }
    current += c;
  }
  flush();
  return values;
}

// The values of `spec` on a .sex line after its key, up to a comment.
std::vector<std::string> tokenizeValue(const KeySpec& spec, std::string_view text) {
  if (spec.expression) return tokenizeExpression(text);
  std::vector<std::string> tokens = tokenize(text);
  const auto comment =
      std::find_if(tokens.begin(), tokens.end(), [](const std::string& t) { return t[0] == '#'; });
  tokens.erase(comment, tokens.end());
  return tokens;
}

// Replaces $NAME and ${NAME} by the environment variable's value, as SExtractor does.
std::string expandEnvironment(const std::string& token, const std::string& where,
                              const std::string& key) {
  std::string out;
  for (std::size_t i = 0; i < token.size();) {
    if (token[i] != '$') {
      out += token[i++];
      continue;
    }
    std::string name;
    std::size_t next;
    if (i + 1 < token.size() && token[i + 1] == '{') {
      const std::size_t close = token.find('}', i + 2);
      if (close == std::string::npos)
        throw ConfigError(where + ": " + key + ": unterminated ${ in " + quoteForMessage(token));
      name = token.substr(i + 2, close - i - 2);
      next = close + 1;
    } else {
      next = i + 1;
      while (next < token.size() &&
             (std::isalnum(static_cast<unsigned char>(token[next])) || token[next] == '_'))
        ++next;
      name = token.substr(i + 1, next - i - 1);
    }
    if (name.empty())
      throw ConfigError(where + ": " + key + ": empty variable name in " + quoteForMessage(token));
    const char* value = std::getenv(name.c_str());
    if (!value)
      throw ConfigError(where + ": " + key + ": environment variable " + quoteForMessage(name) +
                        " is not set");
    out += value;
    i = next;
  }
  return out;
}

// Checks one value against its key and returns its canonical text.
std::string canonicalValue(const KeySpec& spec, const std::string& raw, const std::string& where) {
  auto bad = [&](const std::string& why) {
    return ConfigError(where + ": " + spec.name + " " + quoteForMessage(raw) + ": " + why);
  };
  // A file name or keyword with a NUL, an escape or a line break is never what was meant (a NUL
  // would silently cut a file name), and it would garble every message that shows it.
  if (hasControlCharacter(raw)) throw bad("holds a control character");
  auto checkRange = [&](double v) {
    if (!(v >= spec.minValue && v <= spec.maxValue)) {
      std::ostringstream os;
      os << "out of range [" << spec.minValue << ", " << spec.maxValue << "]";
      throw bad(os.str());
    }
  };
  switch (spec.kind) {
    case KeySpec::Kind::Bool: {
      const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(raw[0])));
      if (c != 'Y' && c != 'N') throw bad("Y or N expected");
      return std::string(1, c);
    }
    case KeySpec::Kind::Int: {
      // strtol with base 0, as SExtractor: 0x1F and 017 are accepted.
      errno = 0;
      char* end = nullptr;
      const long v = std::strtol(raw.c_str(), &end, 0);
      if (end == raw.c_str() || *end != '\0') throw bad("not an integer");
      if (errno == ERANGE) throw bad("integer overflow");
      checkRange(static_cast<double>(v));
      return std::to_string(v);
    }
    case KeySpec::Kind::Float: {
      char* end = nullptr;
      const double v = std::strtod(raw.c_str(), &end);
      if (end == raw.c_str() || *end != '\0' || !std::isfinite(v)) throw bad("not a number");
      checkRange(v);
      return raw;
    }
    case KeySpec::Kind::Keyword: {
      const std::string u = uppercase(raw);
      if (std::find(spec.keywords.begin(), spec.keywords.end(), u) == spec.keywords.end()) {
        std::string allowed;
        for (const auto& k : spec.keywords) allowed += (allowed.empty() ? "" : ", ") + k;
        throw bad("expected one of " + allowed);
      }
      return u;
    }
    case KeySpec::Kind::String:
      return raw;
  }
  return raw;
}

const KeySpec* findSpec(const std::vector<KeySpec>& schema, const std::string& upperKey) {
  for (const auto& spec : schema)
    if (spec.name == upperKey) return &spec;
  return nullptr;
}

std::vector<std::string> validate(const KeySpec& spec, const std::vector<std::string>& raw,
                                  const std::string& where) {
  const int n = static_cast<int>(raw.size());
  if (n < spec.minCount || n > spec.maxCount) {
    std::string joined;
    for (const auto& r : raw) joined += (joined.empty() ? "" : ",") + r;
    std::ostringstream os;
    os << where << ": " << spec.name << " "
       << (joined.empty() ? "(empty)" : quoteForMessage(joined)) << ": expected ";
    if (spec.minCount == spec.maxCount)
      os << spec.minCount;
    else
      os << spec.minCount << " to " << spec.maxCount;
    os << " value(s), got " << n;
    throw ConfigError(os.str());
  }
  std::vector<std::string> out;
  out.reserve(raw.size());
  for (const auto& r : raw)
    out.push_back(canonicalValue(spec, expandEnvironment(r, where, spec.name), where));
  return out;
}

// " (did you mean PREFIXKEY?)" for the key of `schema` nearest to `name`, or "".
std::string suggestion(const std::vector<KeySpec>& schema, std::string_view name,
                       const std::string& prefix) {
  const std::string nearest = nearestKey(schema, name);
  return nearest.empty() ? std::string() : " (did you mean " + prefix + nearest + "?)";
}

}  // namespace

std::string nearestKey(const std::vector<KeySpec>& schema, std::string_view name) {
  const std::string word = uppercase(name);
  std::string best;
  std::size_t bestDistance = std::min<std::size_t>(3, (word.size() + 2) / 3);  // exclusive
  for (const KeySpec& spec : schema) {
    // Levenshtein distance, one row at a time.
    std::vector<std::size_t> row(spec.name.size() + 1);
    for (std::size_t j = 0; j < row.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j < row.size(); ++j) {
        const std::size_t above = row[j];
        row[j] = std::min(
            {row[j] + 1, row[j - 1] + 1, diagonal + (word[i - 1] == spec.name[j - 1] ? 0 : 1)});
        diagonal = above;
      }
    }
    if (row.back() < bestDistance) {
      bestDistance = row.back();
      best = spec.name;
    }
  }
  return best;
}

// A key given with an empty list (a bare "WEIGHT_TYPE" line, "WEIGHT_THRESH ,", or
// -CHECKIMAGE_TYPE "") counts as not given, as in SExtractor: the value stays what it was (the
// default unless set before), for keys whose list may be empty; the others report the count.
void Config::setValue(Value& v, const KeySpec& spec, const std::vector<std::string>& raw,
                      std::string_view given, const std::string& where) {
  std::vector<std::string> text = validate(spec, raw, where);
  v.givenWithoutValue =
      text.empty() && given.substr(0, given.find('#')).find(',') != std::string_view::npos;
  if (text.empty()) return;
  v.text = std::move(text);
  v.isExplicit = true;
  v.where = where;
}

Config Config::load(const std::vector<KeySpec>& schema, const std::string& sexFile,
                    const std::vector<std::pair<std::string, std::string>>& overrides,
                    std::vector<std::string>* warnings, const OverrideOrigin& origin) {
  Config config;
  for (const auto& spec : schema) {
    Value v;
    v.kind = spec.kind;
    v.text = validate(spec, spec.defaults, "default of " + spec.name);
    config.values_[spec.name] = std::move(v);
  }

  if (!sexFile.empty()) {
    std::ifstream in(sexFile);
    if (!in) throw ConfigError(sexFile + ": cannot open configuration file");
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
      ++lineNo;
      const std::size_t keyStart = line.find_first_not_of(kSeparators);
      if (keyStart == std::string::npos || line[keyStart] == '#') continue;
      const std::size_t keyEnd = std::min(line.find_first_of(kSeparators, keyStart), line.size());
      const std::string keyWord = line.substr(keyStart, keyEnd - keyStart);
      const std::string key = uppercase(keyWord);
      const std::string where = sexFile + ":" + std::to_string(lineNo);
      const KeySpec* spec = findSpec(schema, key);
      if (!spec) {
        if (warnings)
          warnings->push_back(where + ": unknown keyword " + quoteForMessage(keyWord) +
                              ", ignored" + suggestion(schema, keyWord, ""));
        continue;
      }
      // The separators between the key and its value ("KEY = value") are not part of it.
      const std::size_t valueStart =
          std::min(line.find_first_not_of(kSeparators, keyEnd), line.size());
      setValue(config.values_[key], *spec,
               tokenizeValue(*spec, std::string_view(line).substr(valueStart)),
               std::string_view(line).substr(keyEnd), where);
    }
    if (in.bad()) throw ConfigError(sexFile + ": read error");
  }

  for (const auto& [rawKey, rawValue] : overrides) {
    std::string key = uppercase(rawKey);
    if (!key.empty() && key[0] == '-') key.erase(0, 1);
    const KeySpec* spec = findSpec(schema, key);
    if (!spec)
      throw ConfigError(origin.name + ": " + quoteForMessage(origin.keyPrefix + rawKey) +
                        ": unknown keyword" + suggestion(schema, key, origin.keyPrefix));
    // The value is one argument that may itself be a comma list ("-CHECKIMAGE_TYPE A,B").
    std::vector<std::string> raw =
        spec->expression ? tokenizeExpression(rawValue) : tokenize(rawValue);
    if (!raw.empty() && raw[0][0] == '#') raw.clear();
    setValue(config.values_[key], *spec, raw, rawValue, origin.name);
  }
  if (warnings) {
    for (const auto& spec : schema) {
      if (!spec.ignored) continue;
      const Value& v = config.values_[spec.name];
      if (!v.isExplicit) continue;
      const bool overridden = v.where == origin.name;
      if (!overridden && v.text == validate(spec, spec.defaults, spec.name)) continue;
      warnings->push_back(v.where + ": " + (overridden ? origin.keyPrefix : "") + spec.name +
                          " is ignored by octarc (setting it has no effect)");
    }
  }
  return config;
}

const Config::Value& Config::find(std::string_view key) const {
  auto it = values_.find(uppercase(key));
  if (it == values_.end()) throw ConfigError(std::string(key) + ": unknown configuration keyword");
  read_.insert(it->first);
  return it->second;
}

namespace {
const std::string& element(std::string_view key, const std::vector<std::string>& text, int i) {
  if (i < 0 || i >= static_cast<int>(text.size()))
    throw ConfigError(std::string(key) + ": no value #" + std::to_string(i + 1) + " (" +
                      std::to_string(text.size()) + " given)");
  return text[static_cast<std::size_t>(i)];
}
}  // namespace

bool Config::getBool(std::string_view key, int i) const {
  const Value& v = find(key);
  if (v.kind != KeySpec::Kind::Bool) throw ConfigError(std::string(key) + ": not a Y/N keyword");
  return element(key, v.text, i) == "Y";
}

int Config::getInt(std::string_view key, int i) const {
  const Value& v = find(key);
  if (v.kind != KeySpec::Kind::Int)
    throw ConfigError(std::string(key) + ": not an integer keyword");
  const long value = std::strtol(element(key, v.text, i).c_str(), nullptr, 10);
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    throw ConfigError(std::string(key) + ": " + std::to_string(value) + " is out of range");
  return static_cast<int>(value);
}

double Config::getDouble(std::string_view key, int i) const {
  const Value& v = find(key);
  if (v.kind != KeySpec::Kind::Int && v.kind != KeySpec::Kind::Float)
    throw ConfigError(std::string(key) + ": not a numeric keyword");
  return std::strtod(element(key, v.text, i).c_str(), nullptr);
}

std::string Config::getString(std::string_view key, int i) const {
  return element(key, find(key).text, i);
}

std::vector<int> Config::getInts(std::string_view key) const {
  std::vector<int> out;
  for (int i = 0; i < count(key); ++i) out.push_back(getInt(key, i));
  return out;
}

std::vector<double> Config::getDoubles(std::string_view key) const {
  std::vector<double> out;
  for (int i = 0; i < count(key); ++i) out.push_back(getDouble(key, i));
  return out;
}

std::vector<std::string> Config::getStrings(std::string_view key) const {
  return find(key).text;
}

int Config::count(std::string_view key) const {
  return static_cast<int>(find(key).text.size());
}

bool Config::has(std::string_view key) const {
  return values_.count(uppercase(key)) != 0;
}

bool Config::isExplicit(std::string_view key) const {
  return find(key).isExplicit;
}

std::string Config::where(std::string_view key) const {
  const Value& v = find(key);
  return v.isExplicit ? v.where : std::string();
}

bool Config::givenWithoutValue(std::string_view key) const {
  return find(key).givenWithoutValue;
}

std::string Config::dump(const std::vector<KeySpec>& schema, bool full) const {
  constexpr std::size_t kValueColumn = 17;    // where values start, as in SExtractor's dump
  constexpr std::size_t kCommentColumn = 32;  // where comments start
  std::ostringstream os;
  os << "# Configuration file written by octarc" << (full ? " (full list)" : "") << "\n#\n";
  for (const auto& spec : schema) {
    if (spec.expertOnly && !full) continue;
    std::string line = spec.name;
    line.append(line.size() < kValueColumn - 1 ? kValueColumn - 1 - line.size() : 0, ' ');
    line += ' ';
    std::string joined;
    for (const auto& t : values_.at(spec.name).text) joined += (joined.empty() ? "" : ",") + t;
    line += joined;
    std::istringstream comment(spec.comment);
    std::string part;
    bool first = true;
    while (std::getline(comment, part)) {
      if (first) {
        line.append(line.size() < kCommentColumn - 1 ? kCommentColumn - 1 - line.size() : 0, ' ');
        os << line << " # " << part << "\n";
        first = false;
      } else {
        os << std::string(kCommentColumn, ' ') << "# " << part << "\n";
      }
    }
    if (first) os << line << "\n";
  }
  return os.str();
}

}  // namespace octarc::sexcompat
