#include "octarc/io/FitsHeader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc {

namespace {

constexpr std::size_t kCardLength = 80;
constexpr std::size_t kKeywordLength = 8;

std::string_view trimRight(std::string_view text) {
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  return text;
}

std::string_view trim(std::string_view text) {
  text = trimRight(text);
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  return text;
}

// The keyword of a card: its first 8 columns, right-trimmed.
std::string_view cardKeyword(std::string_view card) {
  return trimRight(card.substr(0, std::min(card.size(), kKeywordLength)));
}

bool hasValueIndicator(std::string_view card) {
  return card.size() >= 10 && card[8] == '=' && card[9] == ' ';
}

// Commentary keywords never carry a value and may repeat.
bool isCommentary(std::string_view keyword) {
  return keyword.empty() || keyword == "HISTORY" || keyword == "COMMENT";
}

// Parses the value field (column 11 on) of a card: a quoted string with '' escapes, or the
// text before the comment slash.
std::string parseCardValue(std::string_view field) {
  std::size_t pos = 0;
  while (pos < field.size() && field[pos] == ' ') ++pos;
  if (pos < field.size() && field[pos] == '\'') {
    std::string out;
    for (std::size_t i = pos + 1; i < field.size(); ++i) {
      if (field[i] == '\'') {
        if (i + 1 < field.size() && field[i + 1] == '\'') {
          out.push_back('\'');
          ++i;
        } else {
          break;
        }
      } else {
        out.push_back(field[i]);
      }
    }
    // Trailing blanks are not significant in FITS strings; leading ones are.
    return std::string(trimRight(out));
  }
  std::string_view rest = field.substr(pos);
  return std::string(trim(rest.substr(0, rest.find('/'))));
}

// The FITS syntax of an integer or real value: [sign] digits [. [digits]] or [sign] . digits,
// then optionally E or D, [sign], digits. strtod alone would also take "nan", "inf" and hex.
bool isFitsNumber(std::string_view text) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    return i - start;
  };
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
  std::size_t mantissa = digits();
  if (i < text.size() && text[i] == '.') {
    ++i;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (i < text.size() && (text[i] == 'E' || text[i] == 'e' || text[i] == 'D' || text[i] == 'd')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == text.size();
}

std::string padCard(std::string card) {
  if (card.size() > kCardLength) card.resize(kCardLength);
  card.append(kCardLength - card.size(), ' ');
  return card;
}

// The value field (column 11 on) of the first card of `keyword` that has a value, or nullopt.
std::optional<std::string_view> valueField(const std::vector<std::string>& cards,
                                           std::string_view keyword) {
  const std::string key = uppercase(trim(keyword));
  if (isCommentary(key)) return std::nullopt;
  for (const std::string& card : cards) {
    if (cardKeyword(card) == key && hasValueIndicator(card)) {
      return std::string_view(card).substr(10);
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> FitsHeader::value(std::string_view keyword) const {
  const std::optional<std::string_view> field = valueField(cards, keyword);
  if (!field) return std::nullopt;
  return parseCardValue(*field);
}

std::optional<double> FitsHeader::number(std::string_view keyword) const {
  const std::optional<std::string_view> field = valueField(cards, keyword);
  // A string is no number, whatever it reads ('12'): FITS types a value by its form.
  if (!field || trim(*field).substr(0, 1) == "'") return std::nullopt;
  const std::string text = parseCardValue(*field);
  if (!isFitsNumber(text)) return std::nullopt;
  std::string s = text;
  // Fortran-style exponents ("1.5D+03") are legal FITS.
  std::replace(s.begin(), s.end(), 'D', 'E');
  std::replace(s.begin(), s.end(), 'd', 'e');
  const double v = std::strtod(s.c_str(), nullptr);
  if (!std::isfinite(v)) return std::nullopt;  // beyond the range of a double
  return v;
}

void FitsHeader::set(std::string_view keyword, std::string_view rawValue,
                     std::string_view comment) {
  const std::string key = uppercase(trim(keyword));
  if (key.size() > kKeywordLength) {
    throw IoError("FITS keyword '" + key + "' is longer than 8 characters");
  }
  std::string card = key;
  card.append(kKeywordLength - key.size(), ' ');
  if (isCommentary(key)) {
    // Commentary cards: free text from column 9, always appended.
    card += rawValue;
    cards.push_back(padCard(card));
    return;
  }
  card += "= ";
  const std::string_view v = trim(rawValue);
  if (!v.empty() && v.front() == '\'') {
    card += v;  // strings start in column 11
  } else {
    // Fixed format: other values right-justified in columns 11-30.
    if (v.size() < 20) card.append(20 - v.size(), ' ');
    card += v;
  }
  if (card.size() > kCardLength) {
    throw IoError("FITS keyword " + key + ": value does not fit in an 80-character card");
  }
  if (!comment.empty()) {
    card += " / ";
    card += comment;
  }
  card = padCard(card);
  for (std::string& existing : cards) {
    if (cardKeyword(existing) == key && hasValueIndicator(existing)) {
      existing = card;
      return;
    }
  }
  cards.push_back(card);
}

std::string FitsHeader::joined() const {
  std::string out;
  out.reserve(cards.size() * kCardLength);
  for (const std::string& card : cards) out += padCard(card);
  return out;
}

std::string quoteFitsString(std::string_view text) {
  std::string out = "'";
  for (char c : text) {
    out.push_back(c);
    if (c == '\'') out.push_back('\'');
  }
  // The standard asks for at least 8 characters between the quotes.
  if (out.size() < 9) out.append(9 - out.size(), ' ');
  out.push_back('\'');
  return out;
}

}  // namespace octarc
