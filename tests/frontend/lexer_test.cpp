// The re2c lexer: token kinds, exact spans, comments, line starts, errors.
#include <gtest/gtest.h>

#include "frontend/token.h"

using namespace rcxc;
using namespace rcxc::frontend;

namespace {

std::vector<std::string> texts(const std::vector<Token>& toks) {
  std::vector<std::string> out;
  for (const auto& t : toks)
    if (t.kind != TokenKind::End) out.emplace_back(t.text);
  return out;
}

}  // namespace

TEST(Lexer, SplitsOperatorsLongestFirst) {
  Diagnostics d;
  auto toks = lex("a||=b+-=c<<=d>>=e&&f||g==h!=i<=j>=k<<l>>m++n--", 0, d);
  EXPECT_EQ(texts(toks), (std::vector<std::string>{"a", "||=", "b", "+-=", "c", "<<=", "d", ">>=", "e", "&&", "f",
                                                   "||", "g", "==", "h", "!=", "i", "<=", "j", ">=", "k", "<<", "l",
                                                   ">>", "m", "++", "n", "--"}));
  EXPECT_FALSE(d.has_errors());
}

TEST(Lexer, SpansCountLinesAndColumnsFromOne) {
  Diagnostics d;
  auto toks = lex("task main()\n{\n  x = 0x1F;\n}", 7, d);
  ASSERT_EQ(toks.size(), 11u);
  EXPECT_EQ(toks[0].span.begin.file, 7u);
  EXPECT_EQ(toks[1].text, "main");
  EXPECT_EQ(toks[1].span.begin.line, 1u);
  EXPECT_EQ(toks[1].span.begin.column, 6u);
  EXPECT_EQ(toks[1].span.end.column, 10u);
  EXPECT_EQ(toks[5].text, "x");
  EXPECT_EQ(toks[5].span.begin.line, 3u);
  EXPECT_EQ(toks[5].span.begin.column, 3u);
  EXPECT_EQ(toks[7].kind, TokenKind::Number);
  EXPECT_EQ(toks[7].text, "0x1F");
  EXPECT_EQ(toks.back().kind, TokenKind::End);
}

TEST(Lexer, CommentsAreSkippedAndKeepLineNumbers) {
  Diagnostics d;
  auto toks = lex("a /* one\ntwo */ b // rest\nc", 0, d);
  ASSERT_EQ(texts(toks), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(toks[1].span.begin.line, 2u);
  EXPECT_EQ(toks[1].span.begin.column, 8u);
  EXPECT_EQ(toks[2].span.begin.line, 3u);
  EXPECT_TRUE(toks[2].line_start);
  EXPECT_FALSE(toks[1].line_start);
  EXPECT_TRUE(toks[1].space_before);
}

// For the formatter: the comments are listed too, with their spans and
// whether they start their line, and the tokens are the same as without.
TEST(Lexer, CommentsCanBeListedWithoutChangingTheTokens) {
  const std::string text = "a /* one\ntwo */ b // rest\n  /* own */ # define X\nc";
  Diagnostics d;
  std::vector<Comment> comments;
  auto toks = lex(text, 0, d, comments);
  Diagnostics d2;
  auto plain = lex(text, 0, d2);
  ASSERT_EQ(texts(toks), texts(plain));
  ASSERT_EQ(comments.size(), 3u);
  EXPECT_EQ(comments[0].text, "/* one\ntwo */");
  EXPECT_EQ(comments[0].span.begin.line, 1u);
  EXPECT_EQ(comments[0].span.begin.column, 3u);
  EXPECT_EQ(comments[0].span.end.line, 2u);
  EXPECT_EQ(comments[0].span.end.column, 7u);
  EXPECT_FALSE(comments[0].line_start);
  EXPECT_EQ(comments[1].text, "// rest");
  EXPECT_EQ(comments[2].text, "/* own */");
  EXPECT_TRUE(comments[2].line_start);
  // The '#' after a comment at the start of its line still starts a directive.
  ASSERT_EQ(toks[2].text, "#");
  EXPECT_TRUE(toks[2].line_start);
  EXPECT_EQ(toks[2].line_start, plain[2].line_start);
}

// The formatter lexes as the preprocessor does, listing comments too: a
// stray quote is an Unknown token, not reported, and the comments are there.
TEST(Lexer, DeferringStrayCanListCommentsToo) {
  const std::string text = "don't /* c */ ` // d\nx";
  Diagnostics d;
  std::vector<Comment> comments;
  auto toks = lex_deferring_stray(text, 0, d, comments);
  EXPECT_FALSE(d.has_errors());
  ASSERT_EQ(texts(toks), (std::vector<std::string>{"don", "'t /* c */ ` // d", "x"}));
  EXPECT_EQ(toks[1].kind, TokenKind::Unknown);
  EXPECT_TRUE(comments.empty());  // the quote takes the rest of its line
  comments.clear();
  toks = lex_deferring_stray("a /* c */ ` // d", 0, d, comments);
  EXPECT_FALSE(d.has_errors());
  ASSERT_EQ(texts(toks), (std::vector<std::string>{"a", "`"}));
  EXPECT_EQ(toks[1].kind, TokenKind::Unknown);
  ASSERT_EQ(comments.size(), 2u);
  EXPECT_EQ(comments[0].text, "/* c */");
  EXPECT_EQ(comments[1].text, "// d");
}

TEST(Lexer, LineStartMarksDirectivesAndBackslashJoinsLines) {
  Diagnostics d;
  auto toks = lex("#define X \\\n  1\n# if X", 0, d);
  ASSERT_EQ(texts(toks), (std::vector<std::string>{"#", "define", "X", "1", "#", "if", "X"}));
  EXPECT_TRUE(toks[0].line_start);
  EXPECT_FALSE(toks[3].line_start);  // continued line
  EXPECT_TRUE(toks[4].line_start);
}

TEST(Lexer, NumbersAndCharacters) {
  Diagnostics d;
  auto toks = lex("10 010 0x7fff 0XFFFF 'a' '\\n' 99999999999999999999999", 0, d);
  std::int64_t v = 0;
  ASSERT_TRUE(number_value(toks[0], v));
  EXPECT_EQ(v, 10);
  ASSERT_TRUE(number_value(toks[1], v));
  EXPECT_EQ(v, 10);  // nqc reads a leading 0 as decimal, not octal
  ASSERT_TRUE(number_value(toks[2], v));
  EXPECT_EQ(v, 32767);
  ASSERT_TRUE(number_value(toks[3], v));
  EXPECT_EQ(v, 65535);
  EXPECT_EQ(toks[4].kind, TokenKind::Char);
  ASSERT_TRUE(number_value(toks[4], v));
  EXPECT_EQ(v, 97);
  ASSERT_TRUE(number_value(toks[5], v));
  EXPECT_EQ(v, 10);
  ASSERT_TRUE(number_value(toks[6], v));
  EXPECT_GT(v, 0xFFFF);  // too big: reported by sema as not fitting
}

// Character constants take C's escapes, octal and hex ones too; anything
// but one character or one escape is named as a character constant.
TEST(Lexer, CharacterEscapes) {
  Diagnostics d;
  auto toks = lex(R"('\0' '\t' '\\' '\'' '\"' '\101' '\x41' '\xff' '\377' 'ab' '' '\400' '\x100' '\q' '\x')", 0, d);
  std::vector<std::int64_t> want = {0, 9, 92, 39, 34, 65, 65, 255, 255};
  for (std::size_t i = 0; i < want.size(); ++i) {
    std::int64_t v = -1;
    ASSERT_TRUE(number_value(toks[i], v)) << toks[i].text;
    EXPECT_EQ(v, want[i]) << toks[i].text;
  }
  for (std::size_t i = want.size(); i + 1 < toks.size(); ++i) {
    std::int64_t v = 0;
    EXPECT_FALSE(number_value(toks[i], v)) << toks[i].text;
  }
  EXPECT_EQ(toks.size(), want.size() + 6 + 1);
  EXPECT_EQ(invalid_number_message("'ab'"),
            R"(character constant 'ab' must hold one character or one escape (\n \t \r \\ \' \" \0 \101 \x41))");
}

TEST(Lexer, MalformedNumbersAreRejected) {
  Diagnostics d;
  auto toks = lex("12ab 0x", 0, d);
  std::int64_t v = 0;
  EXPECT_FALSE(number_value(toks[0], v));
  EXPECT_FALSE(number_value(toks[1], v));
}

TEST(Lexer, AFractionStaysWithItsNumberAndIsNamedFloatingPoint) {
  // Programs written for other compilers say SetPower(OUT_A, 7.7): one token,
  // reported as what it is rather than as a stray '.'.
  Diagnostics d;
  auto toks = lex("7.7 x 3.", 0, d);
  EXPECT_EQ(texts(toks), (std::vector<std::string>{"7.7", "x", "3."}));
  std::int64_t v = 0;
  EXPECT_FALSE(number_value(toks[0], v));
  EXPECT_EQ(invalid_number_message(toks[0].text),
            "'7.7' is a floating-point number; the RCX computes with 16-bit integers only");
  EXPECT_EQ(invalid_number_message("12ab"), "invalid number '12ab'");
  EXPECT_TRUE(d.all().empty());
}

TEST(Lexer, UnterminatedCommentIsAnErrorAtItsStart) {
  Diagnostics d;
  auto toks = lex("a\n  /* never closed\n", 0, d);
  ASSERT_EQ(d.error_count(), 1u);
  EXPECT_EQ(d.all()[0].message, "unterminated /* comment");
  EXPECT_EQ(d.all()[0].span.begin.line, 2u);
  EXPECT_EQ(d.all()[0].span.begin.column, 3u);
  EXPECT_EQ(toks.back().kind, TokenKind::End);
}

TEST(Lexer, StrayCharactersAreReportedAndLexingGoesOn) {
  Diagnostics d;
  // '@' is nqc's source prefix (@(0x10000 + n)), so only '`' is stray.
  auto toks = lex("a \\ b ` c", 0, d);
  EXPECT_EQ(d.error_count(), 2u);
  EXPECT_EQ(d.all()[0].message, "stray character '\\' in program");
  EXPECT_EQ(d.all()[0].span.begin.column, 3u);
  EXPECT_EQ(toks[4].text, "c");
}

TEST(Lexer, UnterminatedStringStopsAtEndOfLine) {
  Diagnostics d;
  auto toks = lex("\"abc\nx", 0, d);
  ASSERT_EQ(d.error_count(), 1u);
  EXPECT_EQ(d.all()[0].message, "missing terminating \" character");
  EXPECT_EQ(toks[1].text, "x");
}

TEST(Lexer, EmbeddedNulIsAnErrorNotTheEnd) {
  Diagnostics d;
  std::string text("a\0b", 3);
  auto toks = lex(text, 0, d);
  EXPECT_EQ(d.error_count(), 1u);
  EXPECT_EQ(texts(toks), (std::vector<std::string>{"a", "b"}));
}

TEST(Lexer, BinaryInputStopsAfterAFewDozenErrors) {
  Diagnostics d;
  std::string junk(10000, '\x01');
  auto toks = lex(junk, 0, d);
  EXPECT_EQ(d.error_count(), 41u);
  EXPECT_EQ(d.all().back().message, "too many invalid characters; is this an NQC source file?");
  EXPECT_EQ(toks.back().kind, TokenKind::End);
}

TEST(Lexer, UnprintableStrayCharactersAreShownByCode) {
  Diagnostics d;
  lex("a \xfd b", 0, d);
  ASSERT_EQ(d.error_count(), 1u);
  EXPECT_EQ(d.all()[0].message, "stray character '\\xfd' in program");
}

// A letter of another script was two errors, "stray character '\xc3'" and
// "'\xb6'", one per UTF-8 byte, the second caret inside the letter. It is
// one error per character now, naming it, its span the whole character
// (columns count bytes).
TEST(Lexer, ANonAsciiLetterIsOneErrorNamingIt) {
  Diagnostics d;
  auto toks = lex("int gr\xC3\xB6\xC3\x9F" "e;", 0, d);
  ASSERT_EQ(d.error_count(), 2u);
  EXPECT_EQ(d.all()[0].message, "'\xC3\xB6' (U+00F6) cannot be part of a name: NQC names are ASCII letters, digits and _");
  EXPECT_EQ(d.all()[0].span.begin.column, 7u);
  EXPECT_EQ(d.all()[0].span.end.column, 9u);
  EXPECT_EQ(d.all()[1].message, "'\xC3\x9F' (U+00DF) cannot be part of a name: NQC names are ASCII letters, digits and _");
  EXPECT_EQ(d.all()[1].span.begin.column, 9u);
  EXPECT_EQ(d.all()[1].span.end.column, 11u);
  EXPECT_EQ(texts(toks), (std::vector<std::string>{"int", "gr", "\xC3\xB6", "\xC3\x9F", "e", ";"}));
}

// Text copied from a web page or a word processor brings curly quotes,
// dashes for minus signs and non-breaking spaces: each says what to type.
TEST(Lexer, PastedTypographyGetsAHintEach) {
  const std::pair<std::string, std::string> cases[] = {
      {"\xE2\x80\x9C", "'\xE2\x80\x9C' (U+201C) is a typographic quote: use \""},
      {"\xE2\x80\x9D", "'\xE2\x80\x9D' (U+201D) is a typographic quote: use \""},
      {"\xE2\x80\x98", "'\xE2\x80\x98' (U+2018) is a typographic quote: use '"},
      {"\xE2\x80\x99", "'\xE2\x80\x99' (U+2019) is a typographic quote: use '"},
      {"\xC2\xA0", "a non-breaking space (U+00A0): use an ordinary space"},
      {"\xE2\x80\x93", "'\xE2\x80\x93' (U+2013) is an en dash: use -"},
      {"\xE2\x80\x94", "'\xE2\x80\x94' (U+2014) is an em dash: use -"},
      {"\xE2\x88\x92", "'\xE2\x88\x92' (U+2212) is a minus sign: use -"},
      {"\xE2\x89\xA4", "'\xE2\x89\xA4' (U+2264) is a less-than-or-equal sign: use <="},
      {"\xEF\xBC\x9B", "'\xEF\xBC\x9B' (U+FF1B) is a full-width ';': use ;"},
      {"\xE2\x80\x89", "a Unicode space (U+2009): use an ordinary space"},
      {"\xE2\x80\x8B", "an invisible character (U+200B) in program: delete it"},
      {"\xE2\x80\xAE", "an invisible character (U+202E) in program: delete it"},
      {"\xE2\x82\xAC", "stray character '\xE2\x82\xAC' (U+20AC) in program"},
      {"\xF0\x9F\x98\x80", "stray character '\xF0\x9F\x98\x80' (U+1F600) in program"},
  };
  for (const auto& [ch, said] : cases) {
    Diagnostics d;
    lex("x = 3 " + ch + " 1;", 0, d);
    ASSERT_EQ(d.error_count(), 1u) << said;
    EXPECT_EQ(d.all()[0].message, said);
    EXPECT_EQ(d.all()[0].span.begin.column, 7u);
    EXPECT_EQ(d.all()[0].span.end.column, 7u + ch.size()) << said;
  }
}

// Bytes that are no UTF-8 are still one error each, by code.
TEST(Lexer, BytesThatAreNoUtf8AreReportedOneByOne) {
  Diagnostics d;
  lex("a \xC3 b \xC0\xAF c \xE2\x80 d \xB6", 0, d);
  std::vector<std::string> said;
  for (const auto& e : d.all()) said.push_back(e.message);
  EXPECT_EQ(said, (std::vector<std::string>{"stray character '\\xc3' in program", "stray character '\\xc0' in program",
                                            "stray character '\\xaf' in program", "stray character '\\xe2' in program",
                                            "stray character '\\x80' in program", "stray character '\\xb6' in program"}));
}

// A file's tokens can go into the list of a file read before (the
// preprocessor hands each #included part the last part's list): the
// storage is reused, with nothing of the old tokens left, and the tokens
// are those a fresh list gets.
TEST(Lexer, ReusesTheRoomItIsGivenAndDropsWhatItHeld) {
  Diagnostics d;
  std::vector<Token> room = lex("int first_file_with_a_long_name = 1; task main() { Wait(100); }", 3, d);
  const Token* storage = room.data();
  ASSERT_GE(room.capacity(), 12u);
  auto fresh = lex("x = y;", 4, d);
  auto reused = lex("x = y;", 4, d, std::move(room));
  EXPECT_EQ(reused.data(), storage);
  EXPECT_EQ(texts(reused), texts(fresh));
  ASSERT_EQ(reused.size(), fresh.size());
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    EXPECT_EQ(reused[i].kind, fresh[i].kind) << i;
    EXPECT_EQ(reused[i].span.begin.column, fresh[i].span.begin.column) << i;
    EXPECT_EQ(reused[i].span.begin.file, 4u) << i;
    EXPECT_EQ(reused[i].line_start, fresh[i].line_start) << i;
  }
  EXPECT_FALSE(d.has_errors());
}
