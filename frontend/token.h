// Preprocessing tokens: what the re2c lexer produces from one file's text,
// what the preprocessor rearranges, and what the parser finally reads.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "frontend/diagnostics.h"

namespace rcxc::frontend {

enum class TokenKind : std::uint8_t {
  End,         // end of the file
  Identifier,  // keywords too: the parser tells them apart
  Number,      // decimal or 0x hex, as spelled
  Char,        // 'a', as spelled with quotes
  String,      // "text", as spelled with quotes
  Punct,       // operators and punctuation, incl. # ## and $
  Unknown,     // a character that starts no token (reported by lex or by the preprocessor)
};

// The small fields come last, packed together: a file can hold hundreds of
// thousands of tokens, and each byte here is that many. The spelling is a
// view of the file's text in the SourceManager (or of text the preprocessor
// made and keeps there, SourceManager::keep), so a token is a plain value:
// copying or moving one copies 56 bytes and frees nothing.
struct Token {
  std::string_view text;
  SourceSpan span;
  // Macros that must not expand this token again (the "hide set" of the
  // classic expansion algorithm), as an id into the preprocessor's table of
  // interned sets; 0 is the empty set.
  std::uint32_t hide = 0;
  TokenKind kind = TokenKind::End;
  bool line_start = false;    // first token on its line (a directive ends before the next such)
  bool space_before = false;  // whitespace precedes it (for # and -E output)
  // A backslash-newline stands right between this word and the one before
  // (`Wa\` at a line's end, `it` at the next one's start). It joins lines
  // but not words (docs/language.md): a syntax error here says so.
  bool splits_word = false;

  bool is(std::string_view punct) const { return kind == TokenKind::Punct && text == punct; }
  bool is_identifier(std::string_view name) const { return kind == TokenKind::Identifier && text == name; }
};
static_assert(std::is_trivially_copyable_v<Token>, "tokens are copied and moved in bulk");

// The text of the End token of a file whose last comment is never closed:
// the comment took the rest of the file, so what is missing at its end
// (an #endif, a '}') is that comment's doing, not another mistake.
inline constexpr std::string_view kEndInsideComment = "/*";

// Splits `text` (file `file` of the SourceManager) into tokens, ending with
// one End token. The tokens' spellings are views of `text`, which must
// outlive them. Lexical errors (unterminated comment, stray character) are
// reported and lexing goes on. The tokens go into `room`'s storage (what
// it held is dropped): a list of a file read before, so that the parts a
// long program #includes, lexed one after another, fill memory the last
// part already had instead of each faulting in pages of its own.
std::vector<Token> lex(std::string_view text, std::uint32_t file, Diagnostics& diags, std::vector<Token> room = {});

// lex(), except that a character or quote that starts no token (and a NUL)
// is not reported: it is left as an Unknown token, which the preprocessor
// reports with report_unknown_token() only where the text is not left out
// by an #if, so that `#if 0` around prose ("don't", UTF-8 letters) is no
// error, as in C and nqc. Nor does it stop after a few dozen of them.
std::vector<Token> lex_deferring_stray(std::string_view text, std::uint32_t file, Diagnostics& diags,
                                       std::vector<Token> room = {});

// The error for an Unknown token: a stray character, a stray NUL, or a
// quote without its closing one (at the quote).
void report_unknown_token(const Token& t, Diagnostics& diags);

// A comment as written, /* */ or // (without its newline). The compiler
// drops comments; the source formatter (format/) keeps them, so lex() can
// also list them, without changing the tokens it returns.
struct Comment {
  std::string_view text;  // a view of the lexed text, like a token's
  SourceSpan span;
  bool line_start = false;  // nothing but whitespace before it on its line
};
// lex(), also appending every comment of `text`, in order, to `comments`.
std::vector<Token> lex(std::string_view text, std::uint32_t file, Diagnostics& diags,
                       std::vector<Comment>& comments);
// lex_deferring_stray(), also listing the comments: the formatter keeps
// text an #if may leave out (prose with a "don't" in it) as written.
std::vector<Token> lex_deferring_stray(std::string_view text, std::uint32_t file, Diagnostics& diags,
                                       std::vector<Comment>& comments);

// The value of a Number or Char token, or nullopt-like false when malformed.
bool number_value(const Token& t, std::int64_t& value);
// A literal of 2^62 or more: number_value gives this bit with the literal's
// value modulo 2^16 below it, all the target can hold of it, so the checks
// can say it does not fit without naming a number they no longer have.
constexpr std::int64_t kLiteralPastRange = std::int64_t{1} << 62;
// The error for a Number token number_value() cannot read: 7.7 is named as a
// floating-point number (the RCX computes with 16-bit integers only).
std::string invalid_number_message(std::string_view text);

}  // namespace rcxc::frontend
