// A builder for the rows of a key table (Keys.h, and the tables of octarc's own commands):
//   KeyRow("DETECT_MINAREA", Kind::Int, {"5"}, "min. # of pixels above threshold").range(1, 1e9)
// Numeric keys default to SExtractor's range [-BIG, BIG] (BIG = 1e30).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "octarc/sexcompat/Config.h"

namespace octarc::sexcompat {

struct KeyRow {
  static constexpr double kBig = 1e30;  // SExtractor's "BIG"
  KeySpec spec;

  KeyRow(const char* name, KeySpec::Kind kind, std::vector<std::string> defaults,
         std::string comment) {
    spec.name = name;
    spec.kind = kind;
    spec.defaults = std::move(defaults);
    spec.comment = std::move(comment);
    if (kind == KeySpec::Kind::Int || kind == KeySpec::Kind::Float) {
      spec.minValue = -kBig;
      spec.maxValue = kBig;
    }
  }
  KeyRow& range(double lo, double hi) {
    spec.minValue = lo;
    spec.maxValue = hi;
    return *this;
  }
  KeyRow& list(int lo, int hi) {
    spec.minCount = lo;
    spec.maxCount = hi;
    return *this;
  }
  KeyRow& keywords(std::vector<std::string> k) {
    spec.keywords = std::move(k);
    return *this;
  }
  KeyRow& expert() {
    spec.expertOnly = true;
    return *this;
  }
  // Marks a key whose value is muparser text, kept as written (KeySpec::expression).
  KeyRow& expression() {
    spec.expression = true;
    return *this;
  }
  // Marks a key SExtractor has and octarc accepts but does not act on.
  KeyRow& ignored() {
    markIgnored(spec);
    return *this;
  }
  operator KeySpec() const { return spec; }  // NOLINT: table syntax

  // Marks `spec` ignored (KeySpec::ignored) and says so in its comment; also for a key of a
  // table that another command's table builds on.
  static void markIgnored(KeySpec& spec) {
    if (spec.ignored) return;
    spec.ignored = true;
    const auto eol = spec.comment.find('\n');
    spec.comment.insert(eol == std::string::npos ? spec.comment.size() : eol,
                        " (ignored by octarc)");
  }
};

}  // namespace octarc::sexcompat
