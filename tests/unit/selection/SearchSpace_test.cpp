// Search spaces and column expressions: values worked out by hand, the NaN rule, and the errors.
#include "octarc/selection/SearchSpace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "SelectionTestSupport.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc {
namespace {

// Four objects: the first passes the paper's strong-arc cut; the second fails on arcness, the
// third on ellipticity, the fourth has no arcness (NaN).
Table objects() {
  return test::makeTable({{"ARCNESS", {0.2, 0.12, 0.3, kNaN}},
                          {"E_IMAGE", {0.7, 0.8, 0.5, 0.9}},
                          {"SNR_ISO", {50, 100, 45, 60}}});
}

TEST(SearchSpace, TheStrongArcCutKeepsTheRowsThatPassEveryTerm) {
  const SearchSpace space("strong", "ARCNESS > 0.15 && E_IMAGE > 0.6 && SNR_ISO > 40");
  EXPECT_EQ(space.name(), "strong");
  EXPECT_EQ(space.expression(), "ARCNESS > 0.15 && E_IMAGE > 0.6 && SNR_ISO > 40");
  EXPECT_EQ(space.mask(objects()), (std::vector<bool>{true, false, false, false}));
  // 0.10 < a < 0.15 with e > 0.6: the second object only.
  const SearchSpace weak("weak", "ARCNESS > 0.10 && ARCNESS < 0.15 && E_IMAGE > 0.6");
  EXPECT_EQ(weak.mask(objects()), (std::vector<bool>{false, true, false, false}));
  EXPECT_EQ(countSelected(weak.mask(objects())), 1);
  // || and !: everything but the third object, whose e is 0.5; the NaN row never passes.
  const SearchSpace either("either", "!(E_IMAGE < 0.6) || SNR_ISO > 1000");
  EXPECT_EQ(either.mask(objects()), (std::vector<bool>{true, true, false, true}));
}

TEST(ColumnExpression, ValuesOfArithmeticFunctionsAndComparisons) {
  const Table t = objects();
  const auto values = [&](const std::string& text) {
    return ColumnExpression(text, "test").evaluate(t);
  };
  const std::vector<double> snr = values("log10(SNR_ISO)");
  EXPECT_DOUBLE_EQ(snr[0], std::log10(50.0));
  EXPECT_EQ(snr[1], 2.0);  // log10(100)
  // 2 a + 1: 1.4, 1.24, 1.6 (and NaN).
  const std::vector<double> linear = values("2 * ARCNESS + 1");
  EXPECT_DOUBLE_EQ(linear[0], 1.4);
  EXPECT_DOUBLE_EQ(linear[1], 1.24);
  EXPECT_DOUBLE_EQ(linear[2], 1.6);
  EXPECT_TRUE(std::isnan(linear[3]));
  EXPECT_EQ(values("E_IMAGE > 0.6"), (std::vector<double>{1, 1, 0, 1}));
  EXPECT_EQ(values("E_IMAGE > 0.6 ? SNR_ISO : -1"), (std::vector<double>{50, 100, -1, 60}));
  EXPECT_DOUBLE_EQ(values("min(E_IMAGE, 0.75)")[1], 0.75);
  EXPECT_DOUBLE_EQ(values("sqrt(SNR_ISO) ^ 2")[2], 45.0);
  EXPECT_DOUBLE_EQ(values("ln(_e) + abs(-2)")[0], 3.0);  // no column at all
  EXPECT_DOUBLE_EQ(values("log(_e)")[0], 1.0);           // log is the natural logarithm
  const ColumnExpression cut("SNR_ISO > 40 && ARCNESS > E_IMAGE / 4", "test");
  EXPECT_EQ(cut.variables(), (std::vector<std::string>{"ARCNESS", "E_IMAGE", "SNR_ISO"}));
}

TEST(ColumnExpression, ARowWithNanInAUsedColumnIsNan) {
  const Table t = objects();
  // IEEE comparisons would make !(NaN < 0.1) true; the row is NaN instead and never passes.
  const std::vector<double> v = ColumnExpression("!(ARCNESS < 0.1)", "test").evaluate(t);
  EXPECT_EQ(v[0], 1.0);
  EXPECT_TRUE(std::isnan(v[3]));
  // A column the expression does not use does not matter.
  EXPECT_EQ(ColumnExpression("E_IMAGE > 0.6", "test").evaluate(t)[3], 1.0);
}

TEST(ColumnExpression, EveryComparisonOperatorMeansWhatItSays) {
  const Table t = objects();  // ARCNESS 0.2, 0.12, 0.3, NaN
  const auto values = [&](const std::string& text) {
    return ColumnExpression(text, "test").evaluate(t);
  };
  const double nan = kNaN;
  const auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end() - 1, b.begin()) &&
           std::isnan(a.back()) && std::isnan(b.back());
  };
  // On the boundary value 0.2 (the first row) each operator with '=' differs from its strict
  // neighbour.
  EXPECT_TRUE(same(values("ARCNESS >= 0.2"), {1, 0, 1, nan}));
  EXPECT_TRUE(same(values("ARCNESS > 0.2"), {0, 0, 1, nan}));
  EXPECT_TRUE(same(values("ARCNESS <= 0.2"), {1, 1, 0, nan}));
  EXPECT_TRUE(same(values("ARCNESS < 0.2"), {0, 1, 0, nan}));
  EXPECT_TRUE(same(values("ARCNESS == 0.2"), {1, 0, 0, nan}));
  EXPECT_TRUE(same(values("ARCNESS != 0.2"), {0, 1, 1, nan}));
}

TEST(ColumnExpression, AssignmentsAreRefused) {
  using test::expectError;
  // muparser would assign: "FLAGS = 0" is 0 for every row; "E_IMAGE += 1" is no operator.
  expectError<ConfigError>([] { ColumnExpression("E_IMAGE = 0.7", "SEARCH_CUT"); },
                           {"SEARCH_CUT: cannot parse \"E_IMAGE = 0.7\": '=' assigns a value; "
                            "compare with '=='"});
  expectError<ConfigError>([] { ColumnExpression("E_IMAGE === 0.7", "test"); }, {"'=' assigns"});
  expectError<ConfigError>([] { ColumnExpression("E_IMAGE += 1", "LENS_SELECT"); },
                           {"LENS_SELECT: cannot parse \"E_IMAGE += 1\": '=' assigns a value"});
}

TEST(ColumnExpression, AnExpressionUndefinedForEveryRowIsWarnedOfOnce) {
  std::vector<std::string> warned;
  setExpressionWarnings([&](const std::string& text) { warned.push_back(text); });
  // The default sink back however the test ends: the next tests of this process warn too.
  struct RestoreDefaultSink {
    ~RestoreDefaultSink() {
      setExpressionWarnings(
          [](const std::string& text) { std::cerr << "WARNING: " << text << "\n"; });
    }
  } restoreDefaultSink;
  const Table t = objects();
  // Constant, or undefined whatever the row: a division by zero, a function outside its
  // domain, even when a comparison makes the value finite.
  for (const std::string text :
       {"1/0", "sqrt(-1)", "log10(-1) < 1", "ARCNESS/0 > 1", "E_IMAGE > 0 && log10(-1) < 1"}) {
    warned.clear();
    ColumnExpression(text, "LENS_SELECT").evaluate(t);
    ColumnExpression(text, "LENS_SELECT").evaluate(t);  // once only
    ASSERT_EQ(warned.size(), 1u) << text;
    EXPECT_EQ(warned[0], "LENS_SELECT (" + text +
                             "): NaN or infinite (a division by zero, or a function outside its "
                             "domain) for every row, so it does not depend on the data");
  }
  // Defined for some row (log10(ARCNESS - 0.2) is -inf on the first row only), or a NaN that
  // comes from the data: no warning.
  warned.clear();
  for (const std::string text : {"log10(ARCNESS - 0.2) < 0", "ARCNESS > 0.1", "ARCNESS / 2"}) {
    ColumnExpression(text, "test").evaluate(t);
  }
  ColumnExpression("ARCNESS > 0.1", "test").evaluate(test::makeTable({{"ARCNESS", {kNaN}}}));
  EXPECT_TRUE(warned.empty()) << warned.front();
}

TEST(SearchSpace, ErrorsNameTheSpaceAndTheProblem) {
  using test::expectError;
  // Syntax errors: muparser's message with the 0-based position of the fault.
  expectError<ConfigError>([] { SearchSpace("strong", "ARCNESS > "); },
                           {"search space 'strong': cannot parse \"ARCNESS > \"",
                            "Unexpected end of expression at position"});
  expectError<ConfigError>([] { SearchSpace("strong", "ARCNESS > 0.1 &&& E_IMAGE"); },
                           {"search space 'strong'", "cannot parse", "found at position 16"});
  // An unknown function is a name followed by a parenthesis.
  expectError<ConfigError>([] { SearchSpace("strong", "lg10(SNR_ISO) > 1"); },
                           {"search space 'strong'", "Unexpected parenthesis \"(\" at position 4"});
  expectError<ConfigError>([] { SearchSpace("strong", "(ARCNESS > 0.1"); },
                           {"search space 'strong'", "Missing parenthesis"});
  expectError<ConfigError>([] { SearchSpace("strong", "ARCNESS, E_IMAGE"); },
                           {"search space 'strong' (ARCNESS, E_IMAGE)", "gives 2 values"});
  expectError<ConfigError>([] { SearchSpace("strong", "  "); },
                           {"search space 'strong'", "empty expression"});
  expectError<ConfigError>([] { SearchSpace("", "ARCNESS > 0.1"); }, {"needs a name"});
  // An unknown column: its name and the columns there are (scalar ones: vectors are not
  // variables).
  std::vector<ColumnSpec> specs(3);
  specs[0].name = "ARCNESS";
  specs[1].name = "E_IMAGE";
  specs[2].name = "VECTOR_ASSOC";
  specs[2].repeat = 3;
  const Table t(specs);
  expectError<ConfigError>([&] { SearchSpace("strong", "ARCNES > 0.15").mask(t); },
                           {"search space 'strong' (ARCNES > 0.15)", "unknown column ARCNES",
                            "(columns: ARCNESS, E_IMAGE)"});
  expectError<ConfigError>([&] { SearchSpace("s", "VECTOR_ASSOC > 1").mask(t); },
                           {"unknown column VECTOR_ASSOC"});
  // An empty space of simulated arcs: no row passes.
  expectError<ConfigError>([] { SearchSpace("huge", "ARCNESS > 0.5").simulatedMask(objects()); },
                           {"search space 'huge' (ARCNESS > 0.5): no simulated row passes (of 4)"});
  EXPECT_EQ(SearchSpace("strong", "ARCNESS > 0.15").simulatedMask(objects()),
            (std::vector<bool>{true, false, true, false}));
}

}  // namespace
}  // namespace octarc
