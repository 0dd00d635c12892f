#include "frontend/parse.h"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

#include "frontend/nesting.h"
#include "parser.hpp"

namespace rcxc::frontend {

using P = yy::Parser;
using TK = P::token::token_kind_type;

namespace {

struct Spelling {
  std::string_view text;
  TK kind;
};

constexpr Spelling kKeywords[] = {
    {"task", P::token::TASK},     {"sub", P::token::SUB},           {"void", P::token::VOID},
    {"int", P::token::INT},       {"const", P::token::CONST},       {"if", P::token::IF},
    {"else", P::token::ELSE},     {"while", P::token::WHILE},       {"do", P::token::DO},
    {"until", P::token::UNTIL},   {"for", P::token::FOR},           {"repeat", P::token::REPEAT},
    {"switch", P::token::SWITCH}, {"case", P::token::CASE},         {"default", P::token::DEFAULT},
    {"break", P::token::BREAK},   {"continue", P::token::CONTINUE}, {"return", P::token::RETURN},
    {"goto", P::token::GOTO},     {"start", P::token::START},       {"stop", P::token::STOP},
    {"asm", P::token::ASM},       {"true", P::token::TRUE},         {"false", P::token::FALSE},
    {"inline", P::token::INLINE}, {"__source", P::token::SOURCE},   {"__source_arg", P::token::SOURCE_ARG},
    {"abs", P::token::ABS},       {"sign", P::token::SIGN},         {"__nolist", P::token::NOLIST},
    {"__sensor", P::token::SENSOR}, {"__taskid", P::token::TASKID},   {"__type", P::token::TYPE},
};

// Operators of more than one character; one character is its own token.
constexpr Spelling kOperators[] = {
    {"||", P::token::OROR},         {"&&", P::token::ANDAND},       {"==", P::token::EQ},
    {"!=", P::token::NE},           {"<=", P::token::LE},           {">=", P::token::GE},
    {"<<", P::token::SHL},          {">>", P::token::SHR},          {"++", P::token::INC},
    {"--", P::token::DEC},          {"+=", P::token::ADD_ASSIGN},   {"-=", P::token::SUB_ASSIGN},
    {"*=", P::token::MUL_ASSIGN},   {"/=", P::token::DIV_ASSIGN},   {"%=", P::token::MOD_ASSIGN},
    {"&=", P::token::AND_ASSIGN},   {"|=", P::token::OR_ASSIGN},    {"^=", P::token::XOR_ASSIGN},
    {"<<=", P::token::SHL_ASSIGN},  {">>=", P::token::SHR_ASSIGN},  {"||=", P::token::ABS_ASSIGN},
    {"+-=", P::token::SIGN_ASSIGN},
};

// Every token's spelling is looked up here, so the tables are searched by
// first character and length before any comparison (a hash of each
// identifier cost more than the whole search).
template <std::size_t N>
std::optional<TK> find_spelling(const Spelling (&table)[N], std::string_view text) {
  if (text.empty()) return std::nullopt;
  for (const auto& s : table)
    if (s.text[0] == text[0] && s.text.size() == text.size() && s.text == text) return s.kind;
  return std::nullopt;
}

// The keywords by first character (their indexes in kKeywords): an
// identifier is compared with the two or three keywords that start as it
// does instead of a walk through the whole table.
struct KeywordIndex {
  std::uint8_t count[128] = {};
  std::uint8_t keyword[128][6] = {};
};
constexpr KeywordIndex make_keyword_index() {
  KeywordIndex index;
  for (std::size_t k = 0; k < std::size(kKeywords); ++k) {
    auto c = static_cast<unsigned char>(kKeywords[k].text[0]);
    index.keyword[c][index.count[c]++] = static_cast<std::uint8_t>(k);
  }
  return index;
}
constexpr KeywordIndex kKeywordIndex = make_keyword_index();

std::optional<TK> find_keyword(std::string_view text) {
  auto c = static_cast<unsigned char>(text[0]);  // identifiers are never empty
  if (c >= 128) return std::nullopt;
  for (std::uint8_t i = 0; i < kKeywordIndex.count[c]; ++i) {
    const Spelling& s = kKeywords[kKeywordIndex.keyword[c][i]];
    if (s.text == text) return s.kind;
  }
  return std::nullopt;
}

// Tracks `asm { ... }` so that an identifier starting an asm item (after the
// '{' or a ';') and not followed by ',' or '}' is a mnemonic.
bool is_mnemonic_position(Feed& feed, const Token& t) {
  if (feed.asm_stage != 2 || !feed.asm_item_start || feed.asm_depth != 1) return false;
  const Token& next = feed.tokens[feed.pos];
  (void)t;
  return !(next.is(",") || next.is("}"));
}

void track_asm(Feed& feed, const Token& t) {
  if (feed.asm_stage == 0) {
    if (t.is_identifier("asm")) feed.asm_stage = 1;
    return;
  }
  if (feed.asm_stage == 1) {
    if (t.is("{")) {
      feed.asm_stage = 2;
      feed.asm_depth = 1;
      feed.asm_item_start = true;
      // Mnemonic lines start with a name that no ',' or '}' follows.
      const Token& first = feed.tokens[feed.pos];
      const Token& second = feed.tokens[std::min(feed.pos + 1, feed.tokens.size() - 1)];
      feed.asm_byte_list = first.kind != TokenKind::Identifier || second.is(",") || second.is("}");
    } else {
      feed.asm_stage = 0;
    }
    return;
  }
  feed.asm_item_start = false;
  if (t.is("{") || t.is("(")) ++feed.asm_depth;
  if (t.is("}") || t.is(")")) --feed.asm_depth;
  if (feed.asm_depth <= 0) feed.asm_stage = 0;
  if (t.is(";") && feed.asm_depth == 1) feed.asm_item_start = true;
}

// Index just past the ')' that closes the '(' at `open`, or `open` when the
// parentheses are not closed.
std::size_t past_parentheses(const std::vector<Token>& tokens, std::size_t open) {
  int depth = 0;
  for (std::size_t i = open; i < tokens.size() && tokens[i].kind != TokenKind::End; ++i) {
    if (tokens[i].is("(")) ++depth;
    if (tokens[i].is(")") && --depth == 0) return i + 1;
  }
  return open;
}

// The RCX 2 firmware's `monitor (events) { } catch { }` and
// `acquire (resources) { }` statements. Programs written for it would
// otherwise get "expected ';' before '{'". Each is reported once as what it
// is, and its head (and a `catch` or `catch (events)`) is dropped so that the
// blocks parse as plain blocks and the rest of the program is still checked.
// Works in place: the token list is the largest thing the front end
// holds, and a copy of it would double that.
void drop_rcx2_statements(std::vector<Token>& tokens, Diagnostics& diags) {
  std::size_t kept = 0;
  bool head_reported = false;  // a `catch` after it belongs to it and is dropped in silence
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const Token& t = tokens[i];
    const Token* last_kept = kept > 0 ? &tokens[kept - 1] : nullptr;
    // The token is looked at first: the one before it matters only for
    // `monitor` and `acquire`, and this runs over every token.
    auto declared = [&] {  // `void catch()`: a name nqc reserves, which sema reports
      return last_kept && (last_kept->is_identifier("void") || last_kept->is_identifier("sub") ||
                           last_kept->is_identifier("task") || last_kept->is_identifier("inline"));
    };
    bool head = (t.is_identifier("monitor") || t.is_identifier("acquire")) && !declared();
    if (head && i + 1 < tokens.size() && tokens[i + 1].is("(")) {
      std::size_t after = past_parentheses(tokens, i + 1);
      if (after > i + 1 && after < tokens.size() && tokens[after].is("{")) {
        diags
            .error(t.span, t.is_identifier("monitor")
                               ? "'monitor' is an RCX 2 statement (event monitoring); the RCX firmware has no events"
                               : "'acquire' is an RCX 2 statement (resource access); the RCX firmware has none")
            .parsed_past = true;
        head_reported = true;
        i = after - 1;
        continue;
      }
    }
    // A `catch` with no `monitor` or `acquire` before it (`{ ... } catch
    // { ... }`, or one on its own) was dropped in silence, so its block ran
    // as a plain one (nqc: syntax error).
    if (t.is_identifier("catch") && i + 1 < tokens.size() && !declared()) {
      std::size_t after = tokens[i + 1].is("(") ? past_parentheses(tokens, i + 1) : i + 1;
      if (after < tokens.size() && tokens[after].is("{")) {
        if (!head_reported || !last_kept || !last_kept->is("}"))
          diags
              .error(t.span, "'catch' belongs to the RCX 2 firmware's 'monitor' and 'acquire' statements; the "
                             "RCX firmware has neither")
              .parsed_past = true;
        i = after - 1;
        continue;
      }
    }
    if (kept != i) tokens[kept] = std::move(tokens[i]);
    ++kept;
  }
  tokens.resize(kept);
}

}  // namespace

namespace {

// Follows C's `int main(...) {` at the top level (Feed::int_main_body), as
// token `t` is handed out and before the braces it opens or closes count.
void note_int_main(Feed& feed, const Token& t) {
  if (!feed.open_braces.empty()) {
    if (t.is("}") && feed.open_braces.size() == 1 && feed.int_main_body.begin.valid() &&
        !feed.int_main_body.end.valid())
      feed.int_main_body.end = t.span.end;
    return;
  }
  if (t.is("{")) {
    feed.int_main_body = feed.int_main_head ? SourceSpan{t.span.begin, {}} : SourceSpan{};
    feed.int_main_head = false;
  } else if (t.is(";")) {
    feed.int_main_head = false;
  } else if (t.is_identifier("int")) {
    const auto& next = feed.tokens;
    std::size_t i = feed.pos;  // the token after `t`
    feed.int_main_head = i + 1 < next.size() && next[i].is_identifier("main") && next[i + 1].is("(");
  }
}

}  // namespace

bool in_int_main_body(const Feed& feed, const SourceLoc& at) {
  const SourceSpan& body = feed.int_main_body;
  if (!body.begin.valid() || at.file != body.begin.file || before(at, body.begin)) return false;
  return !body.end.valid() || before(at, body.end);
}

yy::Parser::symbol_type next_token(Feed& feed, std::size_t stack_size) {
  feed.deepest_stack = std::max(feed.deepest_stack, stack_size);
  if (stack_size > kMaxParserStack && !feed.too_deep) {
    feed.diags.error(feed.tokens[feed.pos].span, too_deep_message());
    feed.too_deep = true;
  }
  for (;;) {
    const Token& t = feed.tokens[feed.pos];
    if (t.kind == TokenKind::End || feed.too_deep) {
      feed.last_text = {};
      return P::make_END(t.span);
    }
    ++feed.pos;
    feed.prev_end = feed.pos >= 2 ? feed.tokens[feed.pos - 2].span.end : SourceLoc{};
    feed.last_text = t.text;
    note_int_main(feed, t);
    if (t.is("{")) feed.open_braces.push_back(t.span);
    if (t.is("}") && !feed.open_braces.empty()) feed.open_braces.pop_back();
    bool mnemonic = t.kind == TokenKind::Identifier && is_mnemonic_position(feed, t);
    track_asm(feed, t);
    switch (t.kind) {
      case TokenKind::Identifier: {
        if (mnemonic) return P::make_MNEMONIC(t.text, t.span);
        if (auto kind = find_keyword(t.text)) return P::symbol_type(*kind, t.span);
        return P::make_IDENT(t.text, t.span);
      }
      case TokenKind::Number:
      case TokenKind::Char: {
        std::int64_t v = 0;
        if (!number_value(t, v)) {
          feed.diags.error(t.span, invalid_number_message(t.text)).parsed_past = true;
          feed.invalid_number = feed.pos - 1;
        }
        return P::make_NUMBER(v, t.span);
      }
      case TokenKind::String:
        return P::make_STRING(t.span);
      case TokenKind::Punct: {
        if (t.text.size() == 1 && t.text != "#") return P::symbol_type(static_cast<TK>(t.text[0]), t.span);
        if (auto kind = find_spelling(kOperators, t.text)) return P::symbol_type(*kind, t.span);
        feed.diags.error(t.span, "'" + std::string(t.text) + "' is only meaningful in a preprocessor directive");
        continue;
      }
      case TokenKind::Unknown:
        feed.after_unreadable = feed.pos;
        continue;  // already reported by the lexer or the preprocessor
      case TokenKind::End:
        continue;
    }
  }
}

namespace {

// Brackets nested deeper than the tree may be: reported at the first
// bracket too many, and the tokens end there, so that the parser's stack
// never holds more than that many open constructs.
void cut_at_too_deep_brackets(std::vector<Token>& tokens, Diagnostics& diags) {
  int depth = 0;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i].kind != TokenKind::Punct) continue;
    if (tokens[i].is("{") || tokens[i].is("(") || tokens[i].is("[")) {
      if (++depth <= kMaxNesting) continue;
      diags.error(tokens[i].span, "brackets nested more than " + std::to_string(kMaxNesting) + " deep; split it up");
      Token end = tokens.back();  // End
      end.span = tokens[i].span;
      tokens.resize(i);
      tokens.push_back(std::move(end));
      return;
    }
    if (tokens[i].is("}") || tokens[i].is(")") || tokens[i].is("]")) depth = std::max(0, depth - 1);
  }
}

}  // namespace

ast::Program parse_tokens(std::vector<Token> tokens, Diagnostics& diags) {
  drop_rcx2_statements(tokens, diags);
  cut_at_too_deep_brackets(tokens, diags);
  Feed feed{tokens, diags, {}, 0, {}, {}, 0, false, 0, false, {}};
  for (const Diagnostic& d : diags.all())
    if (d.severity == Severity::Error && d.span.begin.expansion != 0) feed.macro_errors.push_back(d.span.begin);
  P parser(feed);
  parser.parse();
  // Walking the whole tree for its depth cost as much as checking it; the
  // parse already bounds that depth. A statement inside others is read
  // while each of them keeps at least one symbol (its `if (c)`, `{`, `do`)
  // on the parser's stack, so statements nest at most as deep as the
  // deepest stack a token was read with; an expression adds its height
  // below its statement. Only when that sum could pass the limit is the
  // tree walked (mixed nesting: tests/frontend/stress_test.cpp).
  constexpr std::size_t kMargin = 8;  // the task/sub head, the body's root
  if (feed.too_deep || feed.deepest_stack + feed.tallest_expr + kMargin > static_cast<std::size_t>(kMaxNesting))
    limit_nesting(feed.program, diags);
  return std::move(feed.program);
}

std::vector<std::string_view> keywords() {
  std::vector<std::string_view> out;
  for (const auto& k : kKeywords) out.push_back(k.text);
  return out;
}

bool is_keyword(std::string_view word) { return !word.empty() && find_keyword(word).has_value(); }

const char* reserved_by_nqc(std::string_view word) {
  if (word == "acquire" || word == "monitor" || word == "catch") return "a statement of the RCX 2 firmware";
  if (word == "__event_src" || word == "__res") return "an intrinsic of other targets";
  return nullptr;
}

const char* not_a_macro_name(std::string_view word) {
  if (const char* why = reserved_by_nqc(word)) return why;
  if (word == "until" || word == "inline" || word == "__source" || word == "__source_arg") return nullptr;
  return is_keyword(word) ? "a keyword" : nullptr;
}

}  // namespace rcxc::frontend
