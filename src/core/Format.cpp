#include "octarc/core/Format.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace octarc {

namespace {

bool isControl(unsigned char c) {
  return c < 0x20 || c == 0x7F;
}

bool isContinuation(unsigned char c) {
  return (c & 0xC0) == 0x80;
}

// Length in bytes of the valid, printable UTF-8 character starting at text[i], or 0 when the
// byte there has to be escaped (a control byte, a C1 control, an invalid or cut sequence).
std::size_t printableLength(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  if (lead < 0x80) return isControl(lead) ? 0 : 1;
  std::size_t length = 0;
  unsigned char low = 0x80;  // allowed range of the second byte (no overlong forms, surrogates)
  unsigned char high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < length; ++k) {
    if (!isContinuation(byte(i + k))) return 0;
  }
  if (lead == 0xC2 && byte(i + 1) <= 0x9F) return 0;  // U+0080..U+009F, the C1 controls
  return length;
}

void appendEscaped(std::string& out, unsigned char c) {
  static const char kHex[] = "0123456789ABCDEF";
  out += "\\x";
  out += kHex[c >> 4];
  out += kHex[c & 0x0F];
}

// The escaped text and the number of characters of the whole input.
struct Escaped {
  std::string text;
  std::size_t totalChars = 0;
};

Escaped escape(std::string_view text, std::size_t maxChars) {
  Escaped out;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = printableLength(text, i);
    const std::size_t step = length == 0 ? 1 : length;
    if (out.totalChars < maxChars) {
      if (length == 0) {
        appendEscaped(out.text, static_cast<unsigned char>(text[i]));
      } else {
        out.text.append(text.substr(i, length));
      }
    }
    ++out.totalChars;
    i += step;
  }
  return out;
}

}  // namespace

std::string quoteForMessage(std::string_view text, std::size_t maxChars) {
  const Escaped e = escape(text, maxChars);
  std::string out = "'" + e.text;
  if (e.totalChars > maxChars) {
    out += "'... (" + std::to_string(e.totalChars) + " characters)";
  } else {
    out += "'";
  }
  return out;
}

std::string printableMessage(std::string_view text, std::size_t maxChars) {
  const Escaped e = escape(text, maxChars);
  if (e.totalChars <= maxChars) return e.text;
  return e.text + "... (" + std::to_string(e.totalChars) + " characters)";
}

bool hasControlCharacter(std::string_view text) {
  for (char c : text) {
    if (isControl(static_cast<unsigned char>(c))) return true;
  }
  return false;
}

std::string escapeHtml(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string lowercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string uppercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string formatNumber(double value, const char* printfFormat, bool dashIfNotFinite) {
  if (dashIfNotFinite && !std::isfinite(value)) return "-";
  char text[64];
  std::snprintf(text, sizeof text, printfFormat, value);
  return text;
}

std::string fitsRealValue(double value, int significantDigits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*G", significantDigits, value);
  std::string out(text);
  if (out.find_first_of(".EN") == std::string::npos) out += ".0";  // N: NAN, INF
  return out;
}

}  // namespace octarc
