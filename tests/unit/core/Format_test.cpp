#include "octarc/core/Format.h"

#include <gtest/gtest.h>

#include <string>

namespace octarc {
namespace {

TEST(Format, PrintableTextIsQuotedUnchanged) {
  EXPECT_EQ(quoteForMessage("MAP_WEIGHT"), "'MAP_WEIGHT'");
  EXPECT_EQ(quoteForMessage(""), "''");
  EXPECT_EQ(quoteForMessage("a b/c.fits[1]"), "'a b/c.fits[1]'");
}

TEST(Format, ControlBytesAreEscaped) {
  EXPECT_EQ(quoteForMessage(std::string("out\0x.cat", 9)), "'out\\x00x.cat'");
  EXPECT_EQ(quoteForMessage("\x1b[31mred"), "'\\x1B[31mred'");
  EXPECT_EQ(quoteForMessage("a\tb\nc\rd\x7f"), "'a\\x09b\\x0Ac\\x0Dd\\x7F'");
}

TEST(Format, ValidUtf8IsKeptInvalidBytesAreEscaped) {
  EXPECT_EQ(quoteForMessage("donn\xc3\xa9\x65s"), "'donn\xc3\xa9\x65s'");  // é: C3 A9
  EXPECT_EQ(quoteForMessage("\xe2\x80\x9csmart\xe2\x80\x9d"),              // U+201C, U+201D
            "'\xe2\x80\x9csmart\xe2\x80\x9d'");
  EXPECT_EQ(quoteForMessage("\xf0\x9f\x94\xad"), "'\xf0\x9f\x94\xad'");  // U+1F52D, 4 bytes
  EXPECT_EQ(quoteForMessage("\xff"), "'\\xFF'");                         // never valid
  EXPECT_EQ(quoteForMessage("\xc3"), "'\\xC3'");                         // cut sequence
  EXPECT_EQ(quoteForMessage("\xc0\xaf"), "'\\xC0\\xAF'");                // overlong '/'
  EXPECT_EQ(quoteForMessage("\xed\xa0\x80"), "'\\xED\\xA0\\x80'");       // surrogate U+D800
  EXPECT_EQ(quoteForMessage("\xc2\x9b"), "'\\xC2\\x9B'");                // C1 control CSI
  EXPECT_EQ(quoteForMessage("\xc2\xa0"), "'\xc2\xa0'");                  // U+00A0 is printable
}

TEST(Format, LongTextIsCutWithItsLength) {
  const std::string longText(5000, 'X');
  const std::string quoted = quoteForMessage(longText);
  EXPECT_EQ(quoted, "'" + std::string(60, 'X') + "'... (5000 characters)");
  // Exactly at the limit nothing is cut.
  EXPECT_EQ(quoteForMessage(std::string(60, 'Y')), "'" + std::string(60, 'Y') + "'");
  // An escaped byte counts as one character of the input.
  EXPECT_EQ(quoteForMessage(std::string(3, '\x01'), 2), "'\\x01\\x01'... (3 characters)");
  // A multi-byte character is never split.
  EXPECT_EQ(quoteForMessage("\xc3\xa9\xc3\xa9\xc3\xa9", 2), "'\xc3\xa9\xc3\xa9'... (3 characters)");
}

TEST(Format, PrintableMessageEscapesWithoutQuotes) {
  EXPECT_EQ(printableMessage("f.fits: bad\nline"), "f.fits: bad\\x0Aline");
  const std::string message = std::string(1500, 'm');
  EXPECT_EQ(printableMessage(message), std::string(1000, 'm') + "... (1500 characters)");
  EXPECT_EQ(printableMessage("abc", 3), "abc");
}

TEST(Format, ControlCharacterTest) {
  EXPECT_FALSE(hasControlCharacter("plain text, with \xc3\xa9"));
  EXPECT_TRUE(hasControlCharacter(std::string("a\0b", 3)));
  EXPECT_TRUE(hasControlCharacter("\x1b"));
  EXPECT_TRUE(hasControlCharacter("\x7f"));
  EXPECT_TRUE(hasControlCharacter("tab\there"));
}

}  // namespace
}  // namespace octarc
