#include "octarc/catalog/FitsCard.h"

#include <cstdio>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

constexpr std::size_t kCardWidth = 80;
constexpr std::size_t kValueWidth = 20;  // columns 11-30, the FITS fixed-format value field

std::string fitCard(std::string card) {
  card.resize(kCardWidth, ' ');
  return card;
}

void checkKeyword(std::string_view key) {
  bool ok = !key.empty() && key.size() <= 8;
  for (char c : key) {
    ok = ok && ((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_');
  }
  if (!ok) throw ConfigError("FITS keyword '" + std::string(key) + "': not a valid keyword");
}

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    out += c;
    if (c == '\'') out += '\'';  // FITS escapes a quote by doubling it
  }
  if (out.size() < 9) out.resize(9, ' ');  // at least 8 characters inside the quotes
  return out + "'";
}

std::string valueField(const CardValue& value) {
  char buffer[64];
  if (const bool* b = std::get_if<bool>(&value)) {
    std::snprintf(buffer, sizeof buffer, "%20s", *b ? "T" : "F");
    return buffer;
  }
  if (const std::int64_t* i = std::get_if<std::int64_t>(&value)) {
    std::snprintf(buffer, sizeof buffer, "%20lld", static_cast<long long>(*i));
    return buffer;
  }
  if (const RealValue* r = std::get_if<RealValue>(&value)) {
    std::snprintf(buffer, sizeof buffer,
                  r->format == RealFormat::Fixed       ? "%20.8f"
                  : r->format == RealFormat::RoundTrip ? "%20.17G"
                                                       : "%20.12E",
                  r->value);
    return buffer;
  }
  std::string s = quoted(std::get<std::string>(value));
  if (s.size() < kValueWidth) s.resize(kValueWidth, ' ');
  return s;
}

}  // namespace

std::string formatCard(std::string_view key, const CardValue& value, std::string_view comment) {
  checkKeyword(key);
  std::string card(key);
  card.resize(8, ' ');
  card += "= ";
  card += valueField(value);
  if (!comment.empty()) {
    card += " / ";
    card += comment;
  }
  return fitCard(std::move(card));
}

std::string formatPlainCard(std::string_view text) {
  return fitCard(std::string(text));
}

}  // namespace octarc
