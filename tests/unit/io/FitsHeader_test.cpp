#include "octarc/io/FitsHeader.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

std::string pad(std::string card) {
  card.resize(80, ' ');
  return card;
}

FitsHeader sample() {
  FitsHeader h;
  h.cards = {pad("SIMPLE  =                    T / conforms"),
             pad("NAXIS1  =                  512"),
             pad("OBJECT  = 'NGC 1234  '         / leading blank kept, trailing dropped"),
             pad("OBSERVER= 'O''Brien and ''co'''"),
             pad("EXPTIME =             1.5D+03 / Fortran exponent"),
             pad("CRVAL1  =   -1.234567890123E+01"),
             pad("EMPTY   = ''"),
             pad("INDENT  = '  x'"),
             pad("HISTORY   not a value = 3"),
             pad("COMMENT = not a value either")};
  return h;
}

TEST(FitsHeader, ValueUnquotesStringsAndHandlesEscapes) {
  const FitsHeader h = sample();
  EXPECT_EQ(h.value("OBJECT"), "NGC 1234");
  EXPECT_EQ(h.value("OBSERVER"), "O'Brien and 'co'");
  EXPECT_EQ(h.value("EMPTY"), "");
  EXPECT_EQ(h.value("INDENT"), "  x");
  EXPECT_EQ(h.value("SIMPLE"), "T");
  EXPECT_EQ(h.value("NAXIS1"), "512");
  EXPECT_EQ(h.value("naxis1"), "512");  // keywords are case-insensitive on lookup
  EXPECT_FALSE(h.value("NAXIS2").has_value());
  EXPECT_FALSE(h.value("HISTORY").has_value());
  EXPECT_FALSE(h.value("COMMENT").has_value());
  EXPECT_TRUE(h.has("EXPTIME"));
  EXPECT_FALSE(h.has("GAIN"));
}

TEST(FitsHeader, NumberParsesFixedAndFortranFormats) {
  const FitsHeader h = sample();
  EXPECT_EQ(h.number("NAXIS1"), 512.0);
  EXPECT_EQ(h.number("EXPTIME"), 1500.0);
  EXPECT_DOUBLE_EQ(*h.number("CRVAL1"), -12.34567890123);
  EXPECT_FALSE(h.number("OBJECT").has_value());
  EXPECT_FALSE(h.number("SIMPLE").has_value());
  EXPECT_FALSE(h.number("MISSING").has_value());
}

TEST(FitsHeader, NumberFollowsTheFitsSyntaxOnly) {
  FitsHeader h;
  const std::vector<std::pair<std::string, std::optional<double>>> cases = {
      {"12", 12.0},       {"-3", -3.0},      {"+4.", 4.0},   {".5", 0.5},
      {"1.5E-3", 1.5e-3}, {"2.0D+01", 20.0}, {"3d2", 300.0}, {"'7.25'", {}},
      {"NaN", {}},        {"nan", {}},       {"Inf", {}},    {"-infinity", {}},
      {"0x10", {}},       {"'x'", {}},       {"1E999", {}},  {"1.5.2", {}},
      {"E5", {}},         {"1E", {}},        {".", {}},      {"T", {}},
      {"(1.0, 2.0)", {}}, {"''", {}},        {"'12'", {}},   {"  '-3' / a string", {}},
  };
  for (const auto& [text, expected] : cases) {
    h.cards = {pad("VALUE   = " + text)};
    EXPECT_EQ(h.number("VALUE"), expected) << text;
  }
}

TEST(FitsHeader, SetFormatsStandardCardsAndReplaces) {
  FitsHeader h;
  h.set("gain", "2.5", "e-/ADU");
  h.set("OBJECT", quoteFitsString("it's"));
  ASSERT_EQ(h.cards.size(), 2u);
  // Fixed format: "= " in columns 9-10, numbers right-justified to column 30.
  EXPECT_EQ(h.cards[0], pad("GAIN    =                  2.5 / e-/ADU"));
  EXPECT_EQ(h.cards[1], pad("OBJECT  = 'it''s   '"));
  EXPECT_EQ(h.value("OBJECT"), "it's");
  h.set("GAIN", "4.0");
  ASSERT_EQ(h.cards.size(), 2u);
  EXPECT_EQ(h.cards[0], pad("GAIN    =                  4.0"));
  EXPECT_EQ(h.number("GAIN"), 4.0);
  h.set("HISTORY", "first");
  h.set("HISTORY", "second");
  h.set("COMMENT", "note");
  ASSERT_EQ(h.cards.size(), 5u);
  EXPECT_EQ(h.cards[2], pad("HISTORY first"));
  EXPECT_EQ(h.cards[3], pad("HISTORY second"));
  EXPECT_EQ(h.cards[4], pad("COMMENT note"));
  for (const std::string& c : h.cards) EXPECT_EQ(c.size(), 80u);
  EXPECT_THROW(h.set("TOOLONGKEY", "1"), IoError);
  EXPECT_THROW(h.set("LONGSTR", quoteFitsString(std::string(75, 'x'))), IoError);
}

TEST(FitsHeader, JoinedConcatenatesEightyCharacterCards) {
  const FitsHeader h = sample();
  const std::string all = h.joined();
  ASSERT_EQ(all.size(), 80u * h.cards.size());
  EXPECT_EQ(all.substr(80, 80), h.cards[1]);
  EXPECT_EQ(FitsHeader{}.joined(), "");
}

TEST(FitsHeader, QuoteFitsStringPadsToEightCharacters) {
  EXPECT_EQ(quoteFitsString("SCI"), "'SCI     '");
  EXPECT_EQ(quoteFitsString("ABCDEFGHIJ"), "'ABCDEFGHIJ'");
  EXPECT_EQ(quoteFitsString("a'b"), "'a''b    '");
}

}  // namespace
}  // namespace octarc
