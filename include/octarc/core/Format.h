// Numbers and user text as octarc prints them: one number formatter for messages, reports and
// header values, and text from files and command lines made fit for a one-line message.
//
// A value read from a user's file may hold anything: a NUL, terminal escape sequences, a line
// break, or thousands of characters. Messages show it through quoteForMessage(), so that an
// error stays one readable line that cannot drive the terminal.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace octarc {

// Longest value, in characters, that quoteForMessage() shows before it cuts.
inline constexpr std::size_t kMessageValueChars = 60;
// Longest message, in characters, that printableMessage() shows before it cuts.
inline constexpr std::size_t kMessageChars = 1000;

// `text` between single quotes, with every control byte (0x00-0x1F, 0x7F), every byte that is
// not part of valid UTF-8 and every UTF-8 C1 control shown as \xNN; printable ASCII and valid
// UTF-8 characters are kept. Beyond `maxChars` characters the text is cut and the total
// length follows: 'XXXX'... (5000 characters).
std::string quoteForMessage(std::string_view text, std::size_t maxChars = kMessageValueChars);

// The same escaping without the quotes, for a whole message (the last guard before a message
// reaches the terminal): cut beyond `maxChars` characters with "... (N characters)".
std::string printableMessage(std::string_view text, std::size_t maxChars = kMessageChars);

// True when `text` holds a control byte (0x00-0x1F or 0x7F).
bool hasControlCharacter(std::string_view text);

// Text for an HTML page: &, <, > and " as entities.
std::string escapeHtml(std::string_view text);

// ASCII case conversions (configuration values, FITS keywords, region shapes, file fields).
std::string lowercase(std::string_view text);
std::string uppercase(std::string_view text);

// `value` through one printf conversion of a double (e.g. "%g", "%.3f", "%.10G"); with
// `dashIfNotFinite`, "-" for NaN and infinities (report tables).
std::string formatNumber(double value, const char* printfFormat = "%g",
                         bool dashIfNotFinite = false);

// A real FITS header value: `significantDigits` digits ("%.nG"), with ".0" appended when the text
// would otherwise read as an integer.
std::string fitsRealValue(double value, int significantDigits);

}  // namespace octarc
