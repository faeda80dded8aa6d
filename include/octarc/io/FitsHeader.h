// A FITS header as its 80-character cards, in file order, without the END card.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace octarc {

struct FitsHeader {
  std::vector<std::string> cards;  // each exactly 80 characters, no END

  // Value of a keyword as written (strings unquoted and right-trimmed), or nullopt.
  std::optional<std::string> value(std::string_view keyword) const;
  // The value as a number when it is written as a FITS integer or real ("12", "-1.5E3",
  // "2.0D-1") and within the range of a double; nullopt otherwise ("NaN", "'x'", absent, and
  // a string that reads as a number, "'12'": FITS types a value by how it is written).
  std::optional<double> number(std::string_view keyword) const;
  bool has(std::string_view keyword) const { return value(keyword).has_value(); }
  // Adds or replaces a card; value is written as given (quote strings yourself, e.g. with
  // quoteFitsString). Strings start in column 11, other values end in column 30. HISTORY,
  // COMMENT and blank keywords take rawValue as free text and are always appended.
  void set(std::string_view keyword, std::string_view rawValue, std::string_view comment = "");
  // All cards joined, as one string of 80*n characters (what wcslib's wcspih takes).
  std::string joined() const;
};

// A FITS string value: quoted, embedded quotes doubled, padded to the 8-character minimum.
std::string quoteFitsString(std::string_view text);

}  // namespace octarc
