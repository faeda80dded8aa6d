// 80-character FITS header cards in the fixed format SExtractor uses for its own keywords.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace octarc {

// How a real value is printed in the 20-character value field.
enum class RealFormat {
  Exponential,  // "%20.12E", e.g. "  1.000000000000E+00" (SEXBKGND, SEXGAIN...)
  Fixed,        // "%20.8f",  e.g. "          2.50000000" (SEXELAPS, SEXMGZPT...)
  RoundTrip,    // "%20.17G": the double itself reads back (values a later run reuses)
};

struct RealValue {
  RealValue(double v, RealFormat f = RealFormat::Exponential) : value(v), format(f) {}
  double value;
  RealFormat format;
};

// A card value: logical (T/F), integer, character string or real.
using CardValue = std::variant<bool, std::int64_t, std::string, RealValue>;

// Formats one card, exactly 80 characters: the keyword left-justified in 8 columns, "= ", the
// value in a 20-character field (strings quoted, at least 8 characters inside the quotes, left
// justified; numbers and logicals right justified), then " / comment" when the comment is not
// empty. Longer content is cut at column 80. Throws ConfigError if the keyword is longer than 8
// characters or not made of FITS keyword characters (A-Z, 0-9, '-', '_').
std::string formatCard(std::string_view key, const CardValue& value, std::string_view comment = "");

// A card without value (e.g. "END", or "COMMENT text"), padded to 80 characters.
std::string formatPlainCard(std::string_view text);

}  // namespace octarc
