#include "lsp/outline.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <tuple>

#include "frontend/token.h"

namespace rcxc::lsp {
namespace {

using frontend::Token;

// Consecutive lines of one kind (// comment lines, #include lines) folded
// together once the run is over.
struct Run {
  FoldKind kind;
  std::uint32_t first = 0, last = 0;

  void add(std::uint32_t line, std::vector<Fold>& out) {
    if (last != 0 && line == last + 1) {
      last = line;
      return;
    }
    flush(out);
    first = last = line;
  }
  void flush(std::vector<Fold>& out) {
    if (last > first) out.push_back({first, last, kind});
    first = last = 0;
  }
};

struct Folder {
  std::vector<Token> tokens;
  std::vector<frontend::Comment> comment_list;
  std::vector<Fold> out;
  Run comment_lines{FoldKind::Comment};
  Run include_lines{FoldKind::Imports};
  std::vector<std::size_t> open_parens;          // token indexes
  std::vector<std::size_t> paren_match;          // by token: the '(' a ')' closes
  std::vector<std::uint32_t> open_braces;        // the first line of each open block
  std::vector<std::uint32_t> open_conditionals;  // the first line of each open #if part

  // The lexer lists comments with their lines: a // comment alone on its
  // line joins a run of such lines, a /* */ comment over lines folds. The
  // lexer's line_start stays true after a comment (`/* a */ // b`), which
  // is not alone on its line.
  void comment(const frontend::Comment& c, const frontend::Comment* before) {
    if (c.text.starts_with("//")) {
      bool after_comment = before != nullptr && before->span.end.line == c.span.begin.line;
      if (c.line_start && !after_comment) comment_lines.add(c.span.begin.line, out);
      return;
    }
    // The line of its last character: an unterminated one ends where the
    // text does, past its last newline.
    close(c.span.begin.line, c.span.end.column == 1 ? c.span.end.line - 1 : c.span.end.line, FoldKind::Comment);
  }

  // The line a block's fold starts on: its header's when the '{' follows
  // `NAME(...)`, `while (...)` or a word (`else`, `do`, `asm`).
  std::uint32_t block_start(std::size_t brace) const {
    std::uint32_t own = tokens[brace].span.begin.line;
    if (brace == 0) return own;
    const Token& before = tokens[brace - 1];
    if (before.kind == frontend::TokenKind::Identifier) return before.span.begin.line;
    if (!before.is(")") || paren_match[brace - 1] == SIZE_MAX) return own;
    std::size_t open = paren_match[brace - 1];
    if (open > 0 && tokens[open - 1].kind == frontend::TokenKind::Identifier) --open;
    return tokens[open].span.begin.line;
  }

  // The last line a fold hides before a closing token: the line before it
  // when it starts its line, so the '}' or '#endif' stays in view.
  static std::uint32_t last_before(const Token& closing) {
    return closing.line_start ? closing.span.begin.line - 1 : closing.span.begin.line;
  }

  void close(std::uint32_t first, std::uint32_t last, FoldKind kind) {
    if (last > first) out.push_back({first, last, kind});
  }

  void directive(std::size_t hash) {
    const Token& name = tokens[hash + 1];
    if (name.kind != frontend::TokenKind::Identifier || name.span.begin.line != tokens[hash].span.begin.line) return;
    std::uint32_t line = name.span.begin.line;
    if (name.text == "include") include_lines.add(line, out);
    if (name.text == "if" || name.text == "ifdef" || name.text == "ifndef") open_conditionals.push_back(line);
    if (open_conditionals.empty()) return;
    if (name.text == "elif" || name.text == "else" || name.text == "endif") {
      close(open_conditionals.back(), last_before(tokens[hash]), FoldKind::Conditional);
      open_conditionals.pop_back();
      if (name.text != "endif") open_conditionals.push_back(line);
    }
  }

  void token(std::size_t i) {
    const Token& t = tokens[i];
    if (t.is("(")) open_parens.push_back(i);
    if (t.is(")") && !open_parens.empty()) {
      paren_match[i] = open_parens.back();
      open_parens.pop_back();
    }
    if (t.is("{")) open_braces.push_back(block_start(i));
    if (t.is("}") && !open_braces.empty()) {
      close(open_braces.back(), last_before(t), FoldKind::Block);
      open_braces.pop_back();
    }
    if (t.is("#") && t.line_start && i + 1 < tokens.size()) directive(i);
  }

  std::vector<Fold> run() {
    paren_match.assign(tokens.size(), SIZE_MAX);
    for (std::size_t i = 0; i < comment_list.size(); ++i) comment(comment_list[i], i > 0 ? &comment_list[i - 1] : nullptr);
    for (std::size_t i = 0; i < tokens.size(); ++i) token(i);
    comment_lines.flush(out);
    include_lines.flush(out);
    auto key = [](const Fold& f) { return std::tuple(f.first, -static_cast<std::int64_t>(f.last), f.kind); };
    std::sort(out.begin(), out.end(), [&](const Fold& a, const Fold& b) { return key(a) < key(b); });
    // Blocks opened on one line and closed on one line fold alike.
    out.erase(std::unique(out.begin(), out.end(), [&](const Fold& a, const Fold& b) { return key(a) == key(b); }), out.end());
    return std::move(out);
  }
};

std::string lowered(std::string_view s) {
  std::string out(s);
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::vector<Fold> folds(std::string_view text) {
  Diagnostics ignored;
  Folder folder;
  folder.tokens = frontend::lex(text, 0, ignored, folder.comment_list);
  return folder.run();
}

std::optional<int> symbol_match(std::string_view name, std::string_view query) {
  const std::string n = lowered(name), q = lowered(query);
  auto at = n.find(q);
  if (at == 0) return 0;
  if (at != std::string::npos) return 1;
  std::size_t next = 0;
  for (char c : n)
    if (next < q.size() && c == q[next]) ++next;
  if (next == q.size()) return 2;
  return std::nullopt;
}

}  // namespace rcxc::lsp
