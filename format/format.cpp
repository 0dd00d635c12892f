// The formatter walks the file's tokens and comments once, in order, keeping
// only what a layout needs to know of the syntax: which braces open blocks,
// which statements are the single statement of an if/while/else, where a
// statement ends. It never needs a parse, so a program with syntax errors
// (a student's) still gets formatted, and nothing is rearranged: only the
// whitespace between tokens changes. The re-lex check at the end is what
// guarantees that, whatever the layout rules get wrong.
#include "format/format.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/token.h"

namespace rcxc::format {
namespace {

using frontend::Token;
using frontend::TokenKind;

// A token or a comment, in the order of the text.
struct Piece {
  std::string_view text;
  SourceSpan span;
  TokenKind kind = TokenKind::End;
  bool comment = false;
  bool line_start = false;
  bool space_before = false;

  bool is(std::string_view punct) const { return !comment && kind == TokenKind::Punct && text == punct; }
  bool is_word(std::string_view word) const { return !comment && kind == TokenKind::Identifier && text == word; }
  bool line_comment() const { return comment && text.starts_with("//"); }
  // A stray character or an unterminated quote (with the rest of its line).
  bool unknown() const { return !comment && kind == TokenKind::Unknown; }
  // Text whose blanks at the end of its line are not kept.
  bool runs_to_line_end() const { return line_comment() || unknown(); }
};

struct Lexed {
  std::vector<Piece> pieces;
  std::string error;  // the first lexical error the lexer reports, "" if none
  SourceLoc error_at{};
};

std::string where(const SourceLoc& loc) {
  return "line " + std::to_string(loc.line) + ", column " + std::to_string(loc.column);
}

bool earlier(const SourceLoc& a, const SourceLoc& b) {
  return a.line < b.line || (a.line == b.line && a.column < b.column);
}

// The compiler's error for an Unknown token it reads, with where it is.
std::string stray_message(const Piece& p) {
  Diagnostics diags;
  Token t;
  t.text = p.text;
  t.span = p.span;
  t.kind = TokenKind::Unknown;
  frontend::report_unknown_token(t, diags);
  const auto& d = diags.all().front();
  return where(d.span.begin) + ": " + d.message;
}

// Lexed as the compiler's preprocessor lexes a file: a stray character or
// an unterminated quote is an Unknown token, an error only where an #if
// does not leave it out (kept_branches() decides what to do with it).
Lexed lex_pieces(std::string_view text) {
  Diagnostics diags;
  std::vector<frontend::Comment> comments;
  std::vector<Token> tokens = frontend::lex_deferring_stray(text, 0, diags, comments);
  Lexed out;
  for (const auto& d : diags.all()) {
    if (d.severity == Severity::Error) {
      out.error = where(d.span.begin) + ": " + d.message;
      out.error_at = d.span.begin;
      break;
    }
  }
  out.pieces.reserve(tokens.size() + comments.size());
  std::size_t c = 0;
  auto take_comment = [&] {
    const auto& k = comments[c++];
    std::size_t at = static_cast<std::size_t>(k.text.data() - text.data());
    bool space = at > 0 && std::string_view(" \t\n\r\v\f").find(text[at - 1]) != std::string_view::npos;
    out.pieces.push_back({k.text, k.span, TokenKind::End, true, k.line_start, space});
  };
  for (const Token& t : tokens) {
    if (t.kind == TokenKind::End) break;
    while (c < comments.size() && comments[c].text.data() < t.text.data()) take_comment();
    out.pieces.push_back({t.text, t.span, t.kind, false, t.line_start, t.space_before});
  }
  while (c < comments.size()) take_comment();
  return out;
}

// ---------------------------------------------------------------------------
// What the compiler sees of a text, for the re-lex check: every token and
// comment in order, with the bounds of each directive (a token moved onto or
// off a directive's line changes the program though the tokens are equal).

enum class Mark : std::uint8_t { Token, Comment, DirectiveBegin, DirectiveEnd };
struct SigItem {
  Mark mark;
  TokenKind kind;
  std::string_view text;
  bool operator==(const SigItem&) const = default;
};

std::string_view trim_right(std::string_view s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\v' || s.back() == '\f'))
    s.remove_suffix(1);
  return s;
}

std::vector<SigItem> signature(const std::vector<Piece>& pieces) {
  std::vector<SigItem> sig;
  sig.reserve(pieces.size() + 8);
  bool in_directive = false;
  for (const Piece& p : pieces) {
    if (p.comment) {
      // A // comment's trailing blanks (a CR of a CRLF file) are not kept.
      sig.push_back({Mark::Comment, TokenKind::End, p.line_comment() ? trim_right(p.text) : p.text});
      continue;
    }
    if (p.line_start && in_directive) {
      sig.push_back({Mark::DirectiveEnd, TokenKind::End, {}});
      in_directive = false;
    }
    // A '#' inside a line starts a directive too, as the preprocessor reads
    // it (nqc's way): code moved onto its line would be taken into it.
    if (p.is("#") && (p.line_start || !in_directive)) {
      sig.push_back({Mark::DirectiveBegin, TokenKind::End, {}});
      in_directive = true;
    }
    sig.push_back({Mark::Token, p.kind, p.unknown() ? trim_right(p.text) : p.text});
  }
  if (in_directive) sig.push_back({Mark::DirectiveEnd, TokenKind::End, {}});
  return sig;
}

// How many pieces come before the first difference of the two signatures
// (the directive marks stand for no piece), for the refusal message.
std::size_t first_changed_piece(const std::vector<SigItem>& want, const std::vector<SigItem>& got) {
  std::size_t pieces = 0;
  for (std::size_t k = 0; k < want.size() && k < got.size() && want[k] == got[k]; ++k)
    pieces += want[k].mark == Mark::Token || want[k].mark == Mark::Comment ? 1 : 0;
  return pieces;
}

// ---------------------------------------------------------------------------
// Words and operators.

bool is_keyword(std::string_view w) {
  static constexpr std::array<std::string_view, 26> kKeywords = {
      "if",   "else",  "while", "do",     "for",   "repeat", "switch", "case",  "default",
      "return", "break", "continue", "until", "task", "sub",  "void",   "int",   "const",
      "inline", "start", "stop",  "asm",    "monitor", "catch", "acquire", "goto"};
  return std::find(kKeywords.begin(), kKeywords.end(), w) != kKeywords.end();
}

// Statements whose header is followed by one statement or a block.
enum class Owner : std::uint8_t { None, If, Else, Do, Loop, Switch, Monitor, Acquire, Catch };

std::optional<Owner> header_owner(const Piece& p) {
  if (p.comment || p.kind != TokenKind::Identifier) return std::nullopt;
  std::string_view w = p.text;
  if (w == "if") return Owner::If;
  if (w == "while" || w == "for" || w == "repeat" || w == "until") return Owner::Loop;
  if (w == "switch") return Owner::Switch;
  if (w == "monitor") return Owner::Monitor;
  if (w == "acquire") return Owner::Acquire;
  if (w == "catch") return Owner::Catch;
  if (w == "else") return Owner::Else;
  if (w == "do") return Owner::Do;
  return std::nullopt;
}

bool is_binary_only(std::string_view op) {
  static constexpr std::array<std::string_view, 27> kBinary = {
      "=",  "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>=", "||=", "+-=", "==",
      "!=", "<",  ">",  "<=", ">=", "&&", "||", "/",  "%",  "|",   "^",   "<<",  ">>"};
  return std::find(kBinary.begin(), kBinary.end(), op) != kBinary.end();
}

// Whether `a` written right before `b` would lex as something else (two
// words running together, `- -` becoming `--`, `/ /` a comment).
bool glues(std::string_view a, std::string_view b) {
  if (a.empty() || b.empty()) return false;
  auto wordish = [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_';
  };
  if (wordish(a.back()) && (wordish(b.front()) || b.front() == '.')) return true;
  if (a.back() == '/' && (b.front() == '/' || b.front() == '*')) return true;
  static constexpr std::array<std::string_view, 23> kLong = {
      "||=", "+-=", "<<=", ">>=", "##", "&&", "||", "==", "!=", "<=", ">=", "<<",
      ">>",  "++",  "--",  "+=",  "-=", "*=", "/=", "%=", "&=", "|=", "^="};
  std::string joined = std::string(a) + std::string(b.substr(0, 3));
  for (std::string_view op : kLong)
    if (op.size() > a.size() && std::string_view(joined).starts_with(op)) return true;
  return false;
}

// ---------------------------------------------------------------------------
// The layout.

// What a line inside a brace or a braceless body is indented for.
enum class FrameKind : std::uint8_t { Block, Switch, Asm, Init, Body };
struct Frame {
  FrameKind kind;
  Owner owner;  // the statement a block or body belongs to
  int levels;   // indentation it adds to the lines inside it
};

// The part of the state a preprocessor conditional restores: each branch of
// #if/#else starts from the nesting before the #if.
struct Nesting {
  std::vector<Frame> frames;
  int level = 0;  // sum of the frames' levels
  int parens = 0;
  int ternaries = 0;  // '?' waiting for their ':'
  bool case_label = false;
  bool do_tail = false;  // the next `while` ends a do statement
  // A header (if, while, ...) whose parenthesis has not closed yet.
  std::optional<Owner> header;
  int header_parens = 0;
  bool header_saw_paren = false;
  Owner brace_owner = Owner::None;  // what the next block's '{' belongs to
};

enum class Role : std::uint8_t { Other, Prefix, Postfix, Binary, Label };

struct Layout {
  Nesting n;
  const Piece* prev_code;
  Role prev_role;
  bool pending_break;
  bool header_ended;
  int statement_level;
  std::size_t statement_first;
};

// An #if being laid out: the layout before it (none when too deep to copy
// cheaply), and whether it stood between statements.
struct Conditional {
  std::optional<Layout> before;
  bool between_statements;
};

constexpr int kMaxIndentLevels = 40;  // deeper code is indented no further
constexpr std::size_t kMaxSnapshotFrames = 256;

struct Printer {
  std::string_view source;
  const std::vector<Piece>& pieces;
  std::vector<std::size_t> next_code;  // index of the next token after i
  Style style;

  std::string out{};
  const Piece* prev = nullptr;       // the last token or comment written
  const Piece* prev_code = nullptr;  // the last token written
  Role prev_role = Role::Other;      // prev_code's
  std::uint32_t prev_end_line = 0;
  bool pending_break = false;  // the next token starts a statement on a new line
  bool header_ended = false;   // a header just closed: a comment here is between statements
  int statement_level = 0;     // the level of the line the current statement started on
  std::size_t statement_first = 0;  // the index of the current statement's first token
  // Macros whose body ends a statement (`;` or `}` last): a use of one on
  // a line of its own is a whole statement, though no `;` follows it.
  std::set<std::string_view> statement_macros{};
  Nesting n{};
  std::vector<Conditional> conditionals{};
  std::vector<std::size_t> kept_begins{};  // the first piece of each branch kept as written, in order
  bool too_large = false;
};

// Where the layout was: what each branch of an #if/#else starts from, and
// what a branch kept as written leaves as it was.
Layout layout_of(const Printer& pr) {
  return {pr.n, pr.prev_code, pr.prev_role, pr.pending_break, pr.header_ended, pr.statement_level, pr.statement_first};
}

void restore(Printer& pr, const Layout& l) {
  pr.n = l.n;
  pr.prev_code = l.prev_code;
  pr.prev_role = l.prev_role;
  pr.pending_break = l.pending_break;
  pr.header_ended = l.header_ended;
  pr.statement_level = l.statement_level;
  pr.statement_first = l.statement_first;
}

const Piece* code_after(const Printer& pr, std::size_t i) {
  std::size_t j = pr.next_code[i];
  return j < pr.pieces.size() ? &pr.pieces[j] : nullptr;
}

bool in_asm(const Printer& pr) { return !pr.n.frames.empty() && pr.n.frames.back().kind == FrameKind::Asm; }

void push_frame(Printer& pr, FrameKind kind, Owner owner) {
  int levels = kind == FrameKind::Init ? 0 : kind == FrameKind::Switch ? 2 : 1;
  pr.n.frames.push_back({kind, owner, levels});
  pr.n.level += levels;
}

Frame pop_frame(Printer& pr) {
  Frame f = pr.n.frames.back();
  pr.n.frames.pop_back();
  pr.n.level -= f.levels;
  return f;
}

void new_line(Printer& pr, int level, bool blank) {
  if (!pr.out.empty()) {
    pr.out += '\n';
    if (blank) pr.out += '\n';
  }
  level = std::clamp(level, 0, kMaxIndentLevels);
  pr.out.append(static_cast<std::size_t>(level * pr.style.indent), ' ');
  // The result must still be a source the compiler reads (and the check
  // lexes it again), so it has the input's cap.
  if (pr.out.size() > kMaxSource) pr.too_large = true;
}

bool blank_before(const Printer& pr, const Piece& p) {
  return pr.prev != nullptr && p.span.begin.line >= pr.prev_end_line + 2;
}

bool on_new_source_line(const Printer& pr, const Piece& p) {
  return pr.prev != nullptr && p.span.begin.line > pr.prev_end_line;
}

// A case label sits one level out from the statements under it.
int level_for(const Printer& pr, const Piece* next) {
  int level = pr.n.level;
  if (next != nullptr && (next->is_word("case") || next->is_word("default")) && !pr.n.frames.empty() &&
      pr.n.frames.back().kind == FrameKind::Switch)
    --level;
  return level;
}

void write(Printer& pr, const Piece& p, Role role) {
  pr.out += p.runs_to_line_end() ? trim_right(p.text) : p.text;
  pr.prev = &p;
  pr.prev_end_line = p.span.end.line;
  if (p.comment) return;
  pr.prev_code = &p;
  pr.prev_role = role;
}

// Inside a statement, past its first token: a line break here continues it.
bool mid_statement(const Printer& pr) { return pr.prev_code != nullptr && !pr.pending_break && !pr.header_ended; }

// Whether the token before ends an operand, making a '-' after it binary.
bool value_end(const Printer& pr) {
  const Piece* p = pr.prev_code;
  if (p == nullptr || !mid_statement(pr)) return false;
  if (pr.prev_role == Role::Postfix) return true;
  switch (p->kind) {
    case TokenKind::Identifier: return !is_keyword(p->text);
    case TokenKind::Number:
    case TokenKind::Char:
    case TokenKind::String: return true;
    case TokenKind::Punct: return p->text == ")" || p->text == "]";
    default: return false;
  }
}

Role role_of(const Printer& pr, const Piece& t) {
  if (t.kind != TokenKind::Punct) return Role::Other;
  std::string_view s = t.text;
  if (s == "!" || s == "~" || s == "$" || s == "@") return Role::Prefix;
  if (s == "++" || s == "--") return value_end(pr) ? Role::Postfix : Role::Prefix;
  if (s == "-" || s == "+" || s == "*" || s == "&") return value_end(pr) ? Role::Binary : Role::Prefix;
  if (s == "?") return Role::Binary;
  if (s == ":") return pr.n.ternaries > 0 ? Role::Binary : Role::Label;
  if (is_binary_only(s)) return Role::Binary;
  return Role::Other;
}

// Whether a space goes between the previous token and `t` on one line.
bool space_between(const Printer& pr, const Piece& t, Role role) {
  const Piece& p = *pr.prev;
  if (glues(p.text, t.text)) return true;
  if (p.comment || t.comment) return t.space_before;
  if (in_asm(pr)) {
    if (t.is(",") || t.is(";")) return false;
    return p.is(",") || t.space_before;
  }
  if (t.is(")") || t.is("]") || t.is(",") || t.is(";")) return false;
  if (role == Role::Label || role == Role::Postfix) return false;
  if (pr.prev_role == Role::Prefix || p.is("(") || p.is("[")) return false;
  if (role == Role::Binary || pr.prev_role == Role::Binary) return true;
  if (p.is(",") || p.is(";")) return true;
  if (t.is("(")) return p.kind == TokenKind::Identifier ? is_keyword(p.text) : !p.is(")") && !p.is("]") && !p.is("{");
  if (t.is("[")) return false;
  if (t.is("}")) return false;
  if (p.is("{")) return false;
  if (role == Role::Prefix || t.is("{")) return true;
  bool word_before = p.kind != TokenKind::Punct && p.kind != TokenKind::Unknown;
  bool word_after = t.kind != TokenKind::Punct && t.kind != TokenKind::Unknown;
  if (word_before && word_after) return true;
  if (p.is(")") && word_after) return true;
  return t.space_before;
}

// A statement (or a block) just ended: the braceless bodies it completes
// end too, up to an if that an else continues or a do its while ends.
void complete(Printer& pr, std::size_t i, Owner owner) {
  const Piece* next = code_after(pr, i);
  for (;;) {
    if (next != nullptr) {
      if (owner == Owner::If && next->is_word("else")) return;
      if ((owner == Owner::Monitor || owner == Owner::Acquire) && next->is_word("catch")) return;
      if (owner == Owner::Do && next->is_word("while")) {
        pr.n.do_tail = true;
        return;
      }
    }
    if (pr.n.frames.empty() || pr.n.frames.back().kind != FrameKind::Body) return;
    owner = pop_frame(pr).owner;
  }
}

void end_statement(Printer& pr, std::size_t i, Owner owner) {
  pr.n.ternaries = 0;
  pr.n.case_label = false;
  complete(pr, i, owner);
  pr.pending_break = true;
}

// The header of an if/while/else... is complete: what follows is a block,
// an empty statement, `if` after else, or one statement on its own line.
void end_header(Printer& pr, std::size_t i, Owner owner) {
  pr.n.header.reset();
  const Piece* next = code_after(pr, i);
  pr.header_ended = true;
  if (next == nullptr || next->is(";")) return;
  if (next->is("{")) {
    pr.n.brace_owner = owner;
    return;
  }
  if (owner == Owner::Else && next->is_word("if")) return;
  push_frame(pr, FrameKind::Body, owner);
  pr.pending_break = true;
}

FrameKind brace_kind(const Printer& pr) {
  const Piece* p = pr.prev_code;
  if (p != nullptr && p->is_word("asm")) return FrameKind::Asm;
  if (p != nullptr && p->is("=")) return FrameKind::Init;
  if (!pr.n.frames.empty() && (pr.n.frames.back().kind == FrameKind::Init || pr.n.frames.back().kind == FrameKind::Asm))
    return FrameKind::Init;
  return pr.n.brace_owner == Owner::Switch ? FrameKind::Switch : FrameKind::Block;
}

// Pops what a '}' closes: braceless bodies left open by a syntax error, then
// its brace. Returns the brace's frame (a Block one if there was none).
Frame close_brace(Printer& pr) {
  while (!pr.n.frames.empty() && pr.n.frames.back().kind == FrameKind::Body) pop_frame(pr);
  if (pr.n.frames.empty()) return {FrameKind::Block, Owner::None, 0};
  return pop_frame(pr);
}

// What a brace token does to the nesting; popped before the token is
// placed, so a '}' goes at the level of what it closes.
struct Brace {
  std::optional<FrameKind> opening;
  std::optional<Frame> closing;
  bool block = false;  // it opens or closes a block or switch body: a line of its own
};

bool is_block(FrameKind k) { return k == FrameKind::Block || k == FrameKind::Switch; }

Brace brace_of(Printer& pr, const Piece& t) {
  Brace b;
  if (t.is("{")) b.opening = brace_kind(pr);
  if (t.is("}")) b.closing = close_brace(pr);
  b.block = (b.opening && is_block(*b.opening)) || (b.closing && is_block(b.closing->kind));
  return b;
}

// Starts a new line for `t` or puts the space before it, if any.
void lead_in(Printer& pr, const Piece& t, Role role, const Brace& b) {
  // Not after `#else`, a directive's last word (a directive writes prev,
  // not prev_code): the `if` on the next line joined it, inside the directive.
  bool joins_else_if = pr.prev != nullptr && pr.prev == pr.prev_code && pr.prev->is_word("else") && t.is_word("if");
  bool source_break = on_new_source_line(pr, t) && !joins_else_if;
  bool asm_line = in_asm(pr) || (b.closing && b.closing->kind == FrameKind::Asm);
  bool first_code = pr.prev_code == nullptr && (pr.prev == nullptr || source_break);
  if (first_code || pr.pending_break || b.block) {
    int level = level_for(pr, &t);
    new_line(pr, level, blank_before(pr, t));
    pr.statement_level = level;
    pr.statement_first = static_cast<std::size_t>(&t - pr.pieces.data());
  } else if (source_break) {
    new_line(pr, asm_line ? level_for(pr, &t) : pr.statement_level + 2, blank_before(pr, t));
  } else if (b.closing && b.closing->kind == FrameKind::Asm ? t.space_before : space_between(pr, t, role)) {
    pr.out += ' ';
  }
}

void after_brace(Printer& pr, std::size_t i, const Brace& b) {
  if (b.opening) {
    if (is_block(*b.opening)) {
      // A block cannot be inside parentheses: what is still open was left
      // open by a syntax error, and the statements inside start afresh.
      pr.n.parens = 0;
      pr.n.header.reset();
    }
    push_frame(pr, *b.opening, is_block(*b.opening) ? pr.n.brace_owner : Owner::None);
    pr.n.brace_owner = Owner::None;
    pr.pending_break = is_block(*b.opening);
  }
  if (b.closing && b.closing->kind != FrameKind::Init) {
    const Piece* next = code_after(pr, i);
    bool attached = next != nullptr && (next->is(";") || next->is(",") || next->is(")"));
    if (!attached) end_statement(pr, i, b.closing->owner);
  }
}

void after_token(Printer& pr, std::size_t i, const Piece& t, Role role);

void place_token(Printer& pr, std::size_t i) {
  const Piece& t = pr.pieces[i];
  Role role = role_of(pr, t);  // before the break: a statement's first '-' is a sign
  Brace b = brace_of(pr, t);
  lead_in(pr, t, role, b);
  pr.pending_break = false;
  pr.header_ended = false;
  write(pr, t, role);
  after_brace(pr, i, b);
  after_token(pr, i, t, role);
}

// A statement keyword: a header to follow (if, while, ... and their
// parenthesis), or one complete already (else, do, catch without one).
void after_keyword(Printer& pr, std::size_t i, const Piece& t) {
  Nesting& n = pr.n;
  if (t.is_word("case") || t.is_word("default")) n.case_label = true;
  std::optional<Owner> owner = header_owner(t);
  if (!owner) return;
  if (t.is_word("while") && n.do_tail) {
    n.do_tail = false;
    return;
  }
  const Piece* next = code_after(pr, i);
  bool parenthesised = next != nullptr && next->is("(");
  if (*owner == Owner::Else || *owner == Owner::Do || (*owner == Owner::Catch && !parenthesised)) {
    end_header(pr, i, *owner);
    return;
  }
  n.header = *owner;
  n.header_parens = n.parens;
  n.header_saw_paren = false;
}

// `t` ends a use of a statement macro that stands alone: the statement
// began with the macro's name, `t` is that name or the ')' closing its
// arguments, and the next token is on a later line and no ';' (a directive
// after it on its line gets a line of its own, so it counts as later).
bool ends_macro_statement(const Printer& pr, std::size_t i, const Piece& t) {
  if (in_asm(pr) || pr.n.parens != 0 || pr.n.header || pr.pending_break) return false;
  const Piece& first = pr.pieces[pr.statement_first];
  if (first.comment || first.kind != TokenKind::Identifier || !pr.statement_macros.contains(first.text)) return false;
  const Piece* next = code_after(pr, i);
  if (next == nullptr || next->is(";") || (next->span.begin.line <= t.span.end.line && !next->is("#"))) return false;
  if (i == pr.statement_first) return !next->is("(");
  const Piece* open = code_after(pr, pr.statement_first);
  return t.is(")") && open != nullptr && open->is("(");
}

void after_token(Printer& pr, std::size_t i, const Piece& t, Role role) {
  Nesting& n = pr.n;
  if (t.is("(") || t.is("[")) {
    ++n.parens;
    if (n.header && t.is("(") && n.parens == n.header_parens + 1) n.header_saw_paren = true;
  } else if (t.is(")") || t.is("]")) {
    n.parens = std::max(0, n.parens - 1);
    if (n.header && n.header_saw_paren && t.is(")") && n.parens == n.header_parens) end_header(pr, i, *n.header);
  } else if (t.is(";")) {
    bool in_for = n.header && n.header_saw_paren && n.parens > 0;
    if (in_asm(pr) || in_for) return;
    n.parens = 0;  // what a syntax error left open ends with the statement
    n.header.reset();
    end_statement(pr, i, Owner::None);
  } else if (t.is("?")) {
    ++n.ternaries;
  } else if (t.is(":") && role == Role::Binary) {
    --n.ternaries;
  } else if (t.is(":") && n.case_label && !in_asm(pr)) {
    n.case_label = false;
    pr.pending_break = true;
  } else if (!in_asm(pr) && n.parens == 0 && t.kind == TokenKind::Identifier) {
    after_keyword(pr, i, t);
  }
  if (ends_macro_statement(pr, i, t)) end_statement(pr, i, Owner::None);
}

void place_comment(Printer& pr, std::size_t i) {
  const Piece& c = pr.pieces[i];
  if (pr.prev == nullptr) {
    new_line(pr, level_for(pr, code_after(pr, i)), false);
  } else if (on_new_source_line(pr, c)) {
    int level = mid_statement(pr) ? pr.statement_level + 2 : level_for(pr, code_after(pr, i));
    new_line(pr, level, blank_before(pr, c));
  } else {
    // On the line of the code before it: the gap is kept, so comments
    // lined up in a column stay lined up.
    std::uint32_t gap = c.span.begin.column > pr.prev->span.end.column ? c.span.begin.column - pr.prev->span.end.column : 0;
    if (pr.prev->span.end.line != c.span.begin.line) gap = 1;
    pr.out.append(gap, ' ');
  }
  write(pr, c, Role::Other);
}

// The physical lines of a directive, from its '#' to the end of its last
// line, with continuation lines that hold no token.
std::string_view directive_text(const Printer& pr, const Piece& first, const Piece& last) {
  std::string_view s = pr.source;
  std::size_t begin = static_cast<std::size_t>(first.text.data() - s.data());
  std::size_t end = static_cast<std::size_t>(last.text.data() - s.data()) + last.text.size();
  for (;;) {
    // After the last token only blanks, and the '\\' that continues the
    // directive onto a line with no token (one inside a // comment does not).
    std::size_t eol = s.find('\n', end);
    if (eol == std::string_view::npos) eol = s.size();
    std::string_view rest = trim_right(s.substr(end, eol - end));
    if (rest.empty() || rest.back() != '\\' || eol == s.size()) return trim_right(s.substr(begin, eol - begin));
    end = eol + 1;
  }
}

// A statement begun inside a branch of an #if that stood between statements
// and left unended there (a note in an #ifdef, half a statement) ends with
// the branch, as a ';' would end it: the code after the #endif is no
// continuation of text the preprocessor may leave out.
void end_branch_statement(Printer& pr, std::size_t last) {
  if (!pr.conditionals.back().between_statements || !(mid_statement(pr) || pr.n.header)) return;
  pr.n.parens = 0;
  pr.n.header.reset();
  end_statement(pr, last, Owner::None);
}

// `last` is the directive's last piece; `kept` says whether the branch it
// opens is kept as written, which leaves the layout as the branch before
// it left it (as if it were not there).
void track_conditional(Printer& pr, std::string_view name, std::size_t last, bool kept) {
  if (name == "if" || name == "ifdef" || name == "ifndef") {
    bool small = pr.n.frames.size() <= kMaxSnapshotFrames;
    pr.conditionals.push_back({small ? std::optional<Layout>(layout_of(pr)) : std::nullopt, !mid_statement(pr)});
  } else if ((name == "elif" || name == "else") && !pr.conditionals.empty()) {
    if (!kept && pr.conditionals.back().before) restore(pr, *pr.conditionals.back().before);
  } else if (name == "endif" && !pr.conditionals.empty()) {
    end_branch_statement(pr, last);
    pr.conditionals.pop_back();
  }
}

// The index of the first piece after the directive whose '#' is piece i:
// a directive ends where a piece starts a line.
std::size_t directive_end(const std::vector<Piece>& pieces, std::size_t i) {
  std::size_t end = i + 1;
  while (end < pieces.size() && !pieces[end].line_start) ++end;
  return end;
}

// Writes the directive starting at piece i as it is written, at the start
// of a line of its own; returns the index of the first piece after it.
std::size_t place_directive(Printer& pr, std::size_t i) {
  std::size_t end = directive_end(pr.pieces, i);
  const Piece& first = pr.pieces[i];
  const Piece& last = pr.pieces[end - 1];
  std::string_view text = directive_text(pr, first, last);
  if (!pr.out.empty()) new_line(pr, 0, blank_before(pr, first));
  pr.out += text;
  pr.prev = &last;
  pr.prev_end_line = first.span.begin.line + static_cast<std::uint32_t>(std::count(text.begin(), text.end(), '\n'));
  // What follows starts a line of its own (the source line after the
  // directive), as a statement if it was between statements, else as a
  // continuation of the one it interrupts.
  if (!mid_statement(pr)) pr.pending_break = true;
  const Piece* name = i + 1 < end ? &pr.pieces[i + 1] : nullptr;
  bool kept = std::binary_search(pr.kept_begins.begin(), pr.kept_begins.end(), end);
  if (name != nullptr && !name->comment && name->kind == TokenKind::Identifier)
    track_conditional(pr, name->text, end - 1, kept);
  return end;
}

std::vector<std::size_t> next_code_table(const std::vector<Piece>& pieces) {
  std::vector<std::size_t> next(pieces.size() + 1, pieces.size());
  for (std::size_t i = pieces.size(); i-- > 0;)
    next[i] = i + 1 < pieces.size() && !pieces[i + 1].comment ? i + 1 : next[i + 1];
  return next;
}

// The macros whose body's last token is `;` or `}`: `#define STOP Off(OUT_A);`,
// `#define TURN(t) { OnRev(OUT_A); Wait(t); }`.
std::set<std::string_view> statement_macros(const std::vector<Piece>& pieces) {
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (pieces[i].comment || !pieces[i].is("#")) continue;
    std::size_t end = directive_end(pieces, i);
    const Piece* last = nullptr;
    for (std::size_t k = i + 3; k < end; ++k)
      if (!pieces[k].comment) last = &pieces[k];
    if (i + 2 < end && pieces[i + 1].is_word("define") && pieces[i + 2].kind == TokenKind::Identifier &&
        last != nullptr && (last->is(";") || last->is("}")))
      names.insert(pieces[i + 2].text);
    i = end - 1;
  }
  return names;
}

// ---------------------------------------------------------------------------
// Branches kept as written: those the preprocessor leaves out whatever the
// macros (#if 0, the #else of an #if 1), and those holding what is no token.
// A left-out branch holds prose and half-written code as often as code, so
// laying it out could mangle it and leave a statement open for the code
// after it. Text that is no token (prose with a "don't" in it) the compiler
// allows in any branch it leaves out; the formatter cannot tell which those
// are (#ifdef depends on -D), so a branch of any conditional holding such a
// thing is kept, and only one outside every conditional is refused.

struct PieceRange {
  std::size_t begin;  // the first piece after the directive opening the branch
  std::size_t end;    // the directive closing it (or the end of the file)
};

struct KeptBranches {
  std::vector<PieceRange> verbatim;  // in order, none inside another
  const Piece* stray = nullptr;      // the first Unknown token outside every conditional
};

// The value of an #if or #elif condition that is a constant without any
// macro: a number, `true` or `false` (the preprocessor's own), under `!`
// and parentheses (`#if 0`, `#elif (1)`, `#if !true`); nullopt for any
// other, whose value the formatter does not work out.
std::optional<bool> constant_condition(const std::vector<Piece>& pieces, std::size_t begin, std::size_t end) {
  std::vector<const Piece*> t;
  for (std::size_t k = begin; k < end; ++k)
    if (!pieces[k].comment) t.push_back(&pieces[k]);
  std::size_t a = 0;
  std::size_t b = t.size();
  bool negated = false;
  for (;;) {
    if (a < b && t[a]->is("!")) {
      negated = !negated;
      ++a;
    } else if (b - a >= 3 && t[a]->is("(") && t[b - 1]->is(")")) {
      ++a;
      --b;
    } else {
      break;
    }
  }
  if (b - a != 1) return std::nullopt;
  const Piece& p = *t[a];
  std::optional<bool> value;
  if (p.is_word("true") || p.is_word("false")) value = p.is_word("true");
  if (p.kind == TokenKind::Number) {
    Token number;
    number.text = p.text;
    number.kind = TokenKind::Number;
    std::int64_t v = 0;
    if (frontend::number_value(number, v)) value = v != 0;
  }
  if (!value) return std::nullopt;
  return *value != negated;
}

KeptBranches kept_branches(const std::vector<Piece>& pieces) {
  struct OpenBranch {
    std::size_t begin;
    bool kept;   // left out whatever the macros, or holding what is no token
    bool taken;  // a branch so far is taken whatever the macros: the rest are left out
  };
  std::vector<OpenBranch> open;
  KeptBranches found;
  auto close = [&](std::size_t end) {
    if (open.back().kept && open.back().begin < end) found.verbatim.push_back({open.back().begin, end});
  };
  for (std::size_t i = 0; i < pieces.size();) {
    const Piece& p = pieces[i];
    if (!p.comment && p.is("#")) {
      std::size_t end = directive_end(pieces, i);
      std::string_view name = i + 1 < end && !pieces[i + 1].comment ? pieces[i + 1].text : "";
      std::optional<bool> value;
      if (name == "if" || name == "elif") value = constant_condition(pieces, i + 2, end);
      if (name == "if" || name == "ifdef" || name == "ifndef") {
        open.push_back({end, value == false, value == true});
      } else if ((name == "elif" || name == "else") && !open.empty()) {
        close(i);
        bool taken = open.back().taken;
        open.back() = {end, taken || (name == "elif" && value == false), taken || value == true};
      } else if (name == "endif" && !open.empty()) {
        close(i);
        open.pop_back();
      }
      i = end;
      continue;
    }
    if (p.unknown() && !open.empty()) open.back().kept = true;
    if (p.unknown() && open.empty() && found.stray == nullptr) found.stray = &p;
    ++i;
  }
  for (; !open.empty(); open.pop_back()) close(pieces.size());
  // An inner branch closes first: order by start, dropping those inside another.
  std::sort(found.verbatim.begin(), found.verbatim.end(),
            [](const PieceRange& a, const PieceRange& b) { return a.begin < b.begin; });
  std::vector<PieceRange> outermost;
  for (const PieceRange& r : found.verbatim)
    if (outermost.empty() || r.begin >= outermost.back().end) outermost.push_back(r);
  found.verbatim = std::move(outermost);
  return found;
}

// The source text of pieces [begin, end) from the start of the first one's
// line, with the blanks that end its lines dropped (and so a CRLF's CR).
std::string verbatim_text(const Printer& pr, PieceRange r) {
  std::string_view s = pr.source;
  std::string out;
  std::size_t from = s.rfind('\n', static_cast<std::size_t>(pr.pieces[r.begin].text.data() - s.data()));
  from = from == std::string_view::npos ? 0 : from + 1;
  for (std::size_t i = r.begin; i < r.end; ++i) {
    const Piece& p = pr.pieces[i];
    std::size_t at = static_cast<std::size_t>(p.text.data() - s.data());
    std::string_view gap = s.substr(from, at - from);
    for (std::size_t eol = gap.find('\n'); eol != std::string_view::npos; eol = gap.find('\n')) {
      out += trim_right(gap.substr(0, eol));
      out += '\n';
      gap.remove_prefix(eol + 1);
    }
    out += gap;
    out += p.runs_to_line_end() ? trim_right(p.text) : p.text;
    from = at + p.text.size();
  }
  return out;
}

void lay_out_pieces(Printer& pr, std::size_t i, std::size_t end) {
  while (i < end && !pr.too_large) {
    const Piece& p = pr.pieces[i];
    // A '#' after code on its line starts a directive too (the
    // preprocessor's reading, nqc's): it is put on a line of its own.
    if (!p.comment && p.is("#")) {
      i = place_directive(pr, i);
      continue;
    }
    if (p.comment)
      place_comment(pr, i);
    else
      place_token(pr, i);
    ++i;
  }
}

// The layout state is left as it was: what follows the branch is laid out
// as if it were not there, its tokens saying nothing of the nesting.
void place_verbatim(Printer& pr, PieceRange r) {
  if (!pr.out.empty()) pr.out += blank_before(pr, pr.pieces[r.begin]) ? "\n\n" : "\n";
  pr.out += verbatim_text(pr, r);
  pr.prev = &pr.pieces[r.end - 1];
  pr.prev_end_line = pr.prev->span.end.line;
  pr.too_large = pr.out.size() > kMaxSource;
}

std::string lay_out(std::string_view source, const std::vector<Piece>& pieces, const std::vector<PieceRange>& verbatim,
                    const Style& style, bool& too_large) {
  Printer pr{.source = source, .pieces = pieces, .next_code = next_code_table(pieces), .style = style};
  pr.statement_macros = statement_macros(pieces);
  for (const PieceRange& r : verbatim) pr.kept_begins.push_back(r.begin);
  pr.out.reserve(source.size() + source.size() / 4 + 16);
  std::size_t i = 0;
  for (const PieceRange& r : verbatim) {
    lay_out_pieces(pr, i, r.begin);
    if (!pr.too_large) place_verbatim(pr, r);
    i = r.end;
  }
  lay_out_pieces(pr, i, pieces.size());
  too_large = pr.too_large;
  // A file ending in a directive's '\\' with no newline after it: a final
  // newline would make that backslash a line continuation (new tokens).
  if (!pr.out.empty() && pr.out.back() != '\\') pr.out += '\n';
  return std::move(pr.out);
}

}  // namespace

std::variant<std::string, Refusal> format_source(std::string_view input, const Style& style) {
  if (input.size() > kMaxSource)
    return Refusal{"cannot format: larger than a source file may be (" + std::to_string(kMaxSource >> 20) + " MiB)"};
  if (style.indent < kMinIndent || style.indent > kMaxIndent)
    return Refusal{"cannot format: the indent must be " + std::to_string(kMinIndent) + " to " + std::to_string(kMaxIndent) + " spaces"};
  // A UTF-8 byte-order mark is no program text (the compiler drops it), so
  // the layout is of what follows it; the mark is written back, as the
  // editor that wrote it wants it. It was refused as a stray character.
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (input.starts_with(kByteOrderMark)) {
    auto rest = format_source(input.substr(kByteOrderMark.size()), style);
    if (auto* formatted = std::get_if<std::string>(&rest)) formatted->insert(0, kByteOrderMark);
    return rest;
  }
  std::string text = with_lone_crs_as_lf(std::string(input));
  Lexed before = lex_pieces(text);
  KeptBranches kept = kept_branches(before.pieces);
  if (kept.stray != nullptr && (before.error.empty() || earlier(kept.stray->span.begin, before.error_at)))
    return Refusal{"cannot format: " + stray_message(*kept.stray)};
  if (!before.error.empty()) return Refusal{"cannot format: " + before.error};
  bool too_large = false;
  std::string out = lay_out(text, before.pieces, kept.verbatim, style, too_large);
  if (too_large)
    return Refusal{"cannot format: the formatted text would be larger than a source file may be (" +
                   std::to_string(kMaxSource >> 20) + " MiB)"};
  Lexed after = lex_pieces(out);
  std::vector<SigItem> want = signature(before.pieces);
  std::vector<SigItem> got = signature(after.pieces);
  if (!after.error.empty() || got != want) {
    std::size_t k = first_changed_piece(want, got);
    std::string place = before.pieces.empty() ? "line 1" : where(before.pieces[std::min(k, before.pieces.size() - 1)].span.begin);
    return Refusal{"cannot format: the layout would change the program's tokens near " + place +
                   " (a formatter bug; please report it with the file)"};
  }
  return out;
}

}  // namespace rcxc::format
