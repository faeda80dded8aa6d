#include "octarc/selection/ColumnExpression.h"

#include <muParser.h>

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <iostream>
#include <limits>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

std::string describe(const std::string& context, const std::string& text) {
  return context + " (" + text + ")";
}

// muparser's message, with the position when the message does not already give it.
std::string parserMessage(const mu::Parser::exception_type& e) {
  std::string message = e.GetMsg();
  if (message.find("position") == std::string::npos && e.GetPos() >= 0) {
    message += " at position " + std::to_string(e.GetPos());
  }
  return message;
}

double logicalNot(double v) {
  return v == 0.0 ? 1.0 : 0.0;
}

// muparser with the prefix operator "!" added (it has && and || but no negation).
void addOperators(mu::Parser& parser) {
  parser.DefineInfixOprt("!", logicalNot);
}

std::string columnList(const Table& table) {
  std::string list;
  for (const ColumnSpec& c : table.columns()) {
    if (c.repeat != 1) continue;
    list += (list.empty() ? "" : ", ") + c.name;
  }
  return list.empty() ? "none" : list;
}

// The floating-point exceptions of an undefined operation: a division by zero (1/0, log10(0))
// or an invalid one (sqrt(-1), log10(-1), 0/0, a comparison with the NaN these give).
constexpr int kUndefinedOperation = FE_DIVBYZERO | FE_INVALID;

struct Warnings {
  std::mutex mutex;
  std::set<std::string> given;
  std::function<void(const std::string&)> sink = [](const std::string& text) {
    std::cerr << "WARNING: " << text << "\n";
  };
};

Warnings& warnings() {
  static Warnings w;
  return w;
}

void warnOnce(const std::string& text) {
  Warnings& w = warnings();
  const std::lock_guard<std::mutex> lock(w.mutex);
  if (w.sink && w.given.insert(text).second) w.sink(text);
}

// A lone '=' (not part of <=, >=, == or !=): muparser's assignment.
bool hasAssignment(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool comparison = std::string("<>!=").find(text[i]) != std::string::npos &&
                            i + 1 < text.size() && text[i + 1] == '=';
    if (comparison) {
      ++i;
    } else if (text[i] == '=') {
      return true;
    }
  }
  return false;
}

}  // namespace

void setExpressionWarnings(std::function<void(const std::string&)> sink) {
  Warnings& w = warnings();
  const std::lock_guard<std::mutex> lock(w.mutex);
  w.sink = std::move(sink);
}

ColumnExpression::ColumnExpression(std::string text, std::string context)
    : text_(std::move(text)), context_(std::move(context)) {
  if (text_.find_first_not_of(" \t") == std::string::npos) {
    throw ConfigError(context_ + ": empty expression");
  }
  if (hasAssignment(text_)) {
    throw ConfigError(context_ + ": cannot parse \"" + text_ +
                      "\": '=' assigns a value; compare with '=='");
  }
  try {
    mu::Parser parser;
    addOperators(parser);
    parser.SetExpr(text_);
    // Parses the whole expression, taking every unknown name for a variable.
    for (const auto& [name, address] : parser.GetUsedVar()) variables_.push_back(name);
    // Bind every variable to a dummy so that the expression can be evaluated once, which
    // counts its results ("a, b" gives two).
    std::vector<double> dummies(variables_.size(), 1.0);
    for (std::size_t i = 0; i < variables_.size(); ++i) {
      parser.DefineVar(variables_[i], &dummies[i]);
    }
    parser.Eval();
    if (parser.GetNumResults() != 1) {
      throw ConfigError(describe(context_, text_) + ": gives " +
                        std::to_string(parser.GetNumResults()) + " values, expected one");
    }
  } catch (const mu::Parser::exception_type& e) {
    throw ConfigError(context_ + ": cannot parse \"" + text_ + "\": " + parserMessage(e));
  }
  std::sort(variables_.begin(), variables_.end());
}

std::vector<double> ColumnExpression::evaluate(const Table& table) const {
  // Where each variable's value sits in a row.
  std::vector<int> offsets;
  for (const std::string& name : variables_) {
    const int c = table.findColumn(name);
    if (c < 0 || table.columns()[std::size_t(c)].repeat != 1) {
      throw ConfigError(describe(context_, text_) + ": unknown column " + name +
                        " (columns: " + columnList(table) + ")");
    }
    offsets.push_back(table.offset(c));
  }
  // A parser of its own per call: evaluation writes into the bound variables, so that calls on
  // several threads never share one.
  std::vector<double> slots(variables_.size(), 0.0);
  std::vector<double> out(std::size_t(table.rows()));
  try {
    mu::Parser parser;
    addOperators(parser);
    for (std::size_t i = 0; i < variables_.size(); ++i) {
      parser.DefineVar(variables_[i], &slots[i]);
    }
    parser.SetExpr(text_);
    // muparser parses at the first Eval and folds constant parts then ("log10(-1) < 1" becomes
    // 0): an undefined operation seen in that first Eval but not when the same row is
    // evaluated again lies in a constant part, undefined for every row.
    bool parsed = false, constantUndefined = false;
    std::int64_t evaluated = 0, undefined = 0;
    for (std::int64_t r = 0; r < table.rows(); ++r) {
      const double* row = table.row(r);
      bool defined = true;
      for (std::size_t i = 0; i < offsets.size(); ++i) {
        slots[i] = row[offsets[i]];
        defined = defined && !std::isnan(slots[i]);
      }
      if (!defined) {
        out[std::size_t(r)] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      bool parseUndefined = false;
      if (!parsed) {
        std::feclearexcept(kUndefinedOperation);
        parser.Eval();
        parseUndefined = std::fetestexcept(kUndefinedOperation) != 0;
        parsed = true;
      }
      std::feclearexcept(kUndefinedOperation);
      const double value = parser.Eval();
      const bool rowUndefined =
          std::fetestexcept(kUndefinedOperation) != 0 || !std::isfinite(value);
      constantUndefined = constantUndefined || (parseUndefined && !rowUndefined);
      out[std::size_t(r)] = value;
      ++evaluated;
      if (rowUndefined) ++undefined;
    }
    if (evaluated > 0 && (constantUndefined || undefined == evaluated)) {
      warnOnce(describe(context_, text_) +
               ": NaN or infinite (a division by zero, or a function outside its domain) for "
               "every row, so it does not depend on the data");
    }
  } catch (const mu::Parser::exception_type& e) {
    throw ConfigError(context_ + ": cannot evaluate \"" + text_ + "\": " + parserMessage(e));
  }
  return out;
}

}  // namespace octarc
