// An arithmetic or logical expression on the columns of a catalog table, e.g.
// "ARCNESS > 0.15 && E_IMAGE > 0.6" or "log10(SNR_ISO)", evaluated with muparser (which stays
// inside src/selection).
//
// Syntax (muparser's): + - * / ^, comparisons < <= > >= == != (1 or 0), && and ||, the prefix
// "!" (not; octarc's addition: it binds tighter than the binary operators, so write
// "!(ARCNESS < 0.1)"), the ternary "c ? a : b", parentheses, numbers such as 0.15 or 1e-3, the
// constants _pi and _e, and the functions log10, ln (= log, the natural logarithm), log2, exp,
// sqrt, abs, sign, rint, min, max, sum, avg and the trigonometric and hyperbolic ones (angles in
// radians). Every scalar column of the table is a variable named exactly as the column
// (case-sensitive); vector columns are not available.
//
// NaN: a row whose value is NaN in any column the expression uses (a measurement that failed,
// or a simulated system without an arc) evaluates to NaN, whatever the expression would make
// of it, so that a failed measurement never passes a cut.
//
// '=' alone is refused: muparser would read "FLAGS = 0" as an assignment (compare with "==").
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "octarc/core/Table.h"

namespace octarc {

class ColumnExpression {
 public:
  // Parses `text`. `context` names the expression in messages, e.g. "search space 'strong'".
  // Throws ConfigError("<context>: ...") for an empty expression or a syntax error (muparser's
  // message and the 0-based position in the expression), or one that yields several values.
  ColumnExpression(std::string text, std::string context);

  const std::string& text() const { return text_; }
  const std::string& context() const { return context_; }
  // The column names the expression uses, sorted.
  const std::vector<std::string>& variables() const { return variables_; }

  // The expression's value for every row of `table` (NaN where a used column is NaN). Throws
  // ConfigError naming the context, the expression, the unknown column and the columns
  // available when a name is not a scalar column of the table. An expression that is undefined
  // for every row whose columns are defined (NaN or infinite: a division by zero, a function
  // outside its domain, such as "1/0", "log10(-1) < 1" or "ARCNESS/0 > 1") selects all or
  // nothing whatever the data: it is warned of (see setExpressionWarnings).
  std::vector<double> evaluate(const Table& table) const;

 private:
  std::string text_;
  std::string context_;
  std::vector<std::string> variables_;
};

// Where the warnings of ColumnExpression::evaluate go, each text once per process: by default
// to stderr as "WARNING: <text>"; an empty function drops them (VERBOSE_TYPE QUIET).
void setExpressionWarnings(std::function<void(const std::string&)> sink);

}  // namespace octarc
