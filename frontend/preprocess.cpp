#include "frontend/preprocess.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "frontend/parse.h"
#include "rcx/file_read.h"
#include "stdlib/stdlib.h"

namespace rcxc::frontend {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxIncludeDepth = 64;
// Macro calls nested inside macro arguments, e.g. F(F(F(...))): each level
// costs a few stack frames, so this also bounds stack use.
constexpr std::size_t kMaxExpansionDepth = 2000;
// Nesting levels of one #if expression: a parenthesis counts two (the
// expression inside it and its operand), a prefix operator or ?: one.
constexpr int kMaxIfNesting = 512;
// Tokens macro expansion may produce in one compilation: a base plus a
// multiple of the tokens read from files. Far above what real programs need
// (the stdlib's macros add a few tokens each), low enough that exponentially
// growing macros stop in well under a second.
constexpr std::size_t kExpansionBase = 500'000;
constexpr std::size_t kExpansionPerInputToken = 32;
// Argument tokens the macro calls being expanded at one time hold together
// (live_argument_tokens_), counted as if each level kept its own copy. An
// argument used once is moved into its expansion rather than copied, so
// memory stays near the input's size, but the count still bounds the work:
// F(F(F(...))) rescans what is inside at every level. 1000 nested calls of
// a one-parameter macro (tests/frontend/stress_test.cpp) count about 2.5
// million; F(F(F(...))) 10,000 deep stops here in a third of a second with
// 17 MB (it once took 8 GB).
constexpr std::size_t kLiveArgumentBase = 3'000'000;
constexpr std::size_t kLiveArgumentPerInputToken = 4;
constexpr const char* kStdlibName = "rcx.nqh";

// Macro names, looked up by a token's spelling (a view) without making a
// string of it.
struct NameHash {
  using is_transparent = void;
  std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};
using MacroIds = std::unordered_map<std::string, std::uint32_t, NameHash, std::equal_to<>>;

struct Macro {
  std::string name;
  bool function_like = false;
  std::vector<std::string> params;
  std::vector<Token> body;
  SourceSpan span;  // the name in its #define
  // nqc's `until(c)`, a macro for `while (!(c))` that rcxc's parser reads as
  // a statement: defined to #ifdef and defined(), never expanded.
  bool statement = false;
  // A function-like body nqc would turn into a syntax error where it is
  // used ('#' before no parameter, '##' at an end): the error waits for a
  // use, since nqc compiles a program that defines such a macro and never
  // calls it. Empty when the body is sound.
  std::string unusable;
  SourceSpan unusable_at;
};

// One file being read: its tokens and where we are in them.
struct OpenFile {
  std::vector<Token> tokens;
  std::size_t pos = 0;
  std::uint32_t file = 0;
  std::string dir;   // folder for quoted includes ("" for embedded files)
  std::string key;   // identity for cycle detection
  std::size_t conds_at_entry = 0;
};

// One #if/#ifdef/#ifndef group being read.
struct Cond {
  bool parent_active = true;
  bool active = false;  // the current branch is being read
  bool taken = false;   // some branch of the group was taken
  bool seen_else = false;
  SourceSpan span;
};

// A place tokens come from: a stack of pending tokens (macro output, next
// token at the back), and, for the main stream, the open files after it.
struct Stream {
  std::vector<Token> stack;
  bool reads_files = false;
};

// Hide sets are interned: each distinct set of macro ids is stored once and
// tokens carry its index, so expansion copies no vectors and set operations
// are cached.
class HideSets {
 public:
  HideSets() { sets_.emplace_back(); }

  bool contains(std::uint32_t set, std::uint32_t macro) const {
    const auto& v = sets_[set];
    return std::binary_search(v.begin(), v.end(), macro);
  }
  // Every expansion adds its macro to a set: cached like the others, so
  // the thousandth use of OUT_A copies and looks up no vector.
  std::uint32_t with(std::uint32_t set, std::uint32_t macro) {
    return cached(with_cache_, set, macro, [&] {
      std::vector<std::uint32_t> v = sets_[set];
      auto at = std::lower_bound(v.begin(), v.end(), macro);
      if (at == v.end() || *at != macro) v.insert(at, macro);
      return v;
    });
  }
  std::uint32_t unite(std::uint32_t a, std::uint32_t b) {
    if (a == b || b == 0) return a;
    if (a == 0) return b;
    return cached(union_cache_, a, b, [&] {
      std::vector<std::uint32_t> v;
      std::set_union(sets_[a].begin(), sets_[a].end(), sets_[b].begin(), sets_[b].end(), std::back_inserter(v));
      return v;
    });
  }
  std::uint32_t intersect(std::uint32_t a, std::uint32_t b) {
    if (a == b) return a;
    if (a == 0 || b == 0) return 0;
    return cached(intersect_cache_, a, b, [&] {
      std::vector<std::uint32_t> v;
      std::set_intersection(sets_[a].begin(), sets_[a].end(), sets_[b].begin(), sets_[b].end(),
                            std::back_inserter(v));
      return v;
    });
  }

 private:
  std::vector<std::vector<std::uint32_t>> sets_;
  std::map<std::vector<std::uint32_t>, std::uint32_t> index_;
  std::unordered_map<std::uint64_t, std::uint32_t> union_cache_, intersect_cache_, with_cache_;

  std::uint32_t intern(std::vector<std::uint32_t> v) {
    auto [it, fresh] = index_.emplace(std::move(v), static_cast<std::uint32_t>(sets_.size()));
    if (fresh) sets_.push_back(it->first);
    return it->second;
  }
  template <class F>
  std::uint32_t cached(std::unordered_map<std::uint64_t, std::uint32_t>& cache, std::uint32_t a, std::uint32_t b,
                       F compute) {
    std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | b;
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    std::uint32_t id = intern(compute());
    cache.emplace(key, id);
    return id;
  }
};

std::string spell(const std::vector<Token>& toks, std::size_t from = 0) {
  std::string s;
  for (std::size_t i = from; i < toks.size(); ++i) {
    if (i > from && toks[i].space_before) s += ' ';
    s += toks[i].text;
  }
  return s;
}

SourceSpan span_of(const std::vector<Token>& toks, std::size_t from, SourceSpan fallback) {
  if (from >= toks.size()) return fallback;
  return {toks[from].span.begin, toks.back().span.end};
}

}  // namespace

// What reading rcx.nqh leaves behind: the preprocessor's macros and hide
// sets, the stdlib's tokens, and what it added to the SourceManager (the
// command line's pseudo-file, rcx.nqh itself, the macro uses in it).
struct StdlibState {
  std::vector<std::pair<std::string, std::string>> defines;
  std::vector<std::string> undefines;
  std::uint32_t first_file = 0;  // the SourceManager's size before it
  struct File {
    std::string path;
    std::string text;
    bool library = false;
  };
  std::vector<File> files;
  std::vector<MacroExpansion> expansions;
  std::vector<Macro> macros;
  MacroIds defined;
  std::unordered_set<std::string> reported_recursion;
  HideSets hide_sets;
  std::size_t expanded_tokens = 0;
  std::size_t input_tokens = 0;
  ast::Pragmas pragmas;
  std::vector<Token> tokens;  // the stdlib's output, without End
  // The SourceManager it was read with: the tokens above and the macros'
  // bodies are views of the texts it keeps.
  SourceManager texts;
};

namespace {

class Preprocessor {
 public:
  Preprocessor(const Options& o, SourceManager& sm, Diagnostics& d) : opts_(o), sm_(sm), diags_(d) {}

  Preprocessed run(std::uint32_t file, const std::string& dir) {
    define_builtins();
    push_file(file, dir, sm_.path(file));
    out_.pragmas.program_init = opts_.no_stdlib;
    if (!opts_.no_stdlib) {
      if (auto text = stdlib::find(kStdlibName)) {
        std::uint32_t id = sm_.add(kStdlibName, std::string(*text));
        sm_.mark_library(id);
        push_file(id, "", std::string("<stdlib>/") + kStdlibName);
      } else {
        diags_.error({}, "the standard library rcx.nqh is missing from this build");
      }
    }
    return read_all();
  }

  // As run(), from the state rcx.nqh left instead of reading it again; the
  // tokens are the file's own.
  Preprocessed run_after(const StdlibState& stdlib, std::uint32_t file, const std::string& dir) {
    for (const auto& f : stdlib.files) {
      std::uint32_t id = sm_.add(f.path, f.text);
      if (f.library) sm_.mark_library(id);
    }
    for (const auto& e : stdlib.expansions) sm_.add_expansion(e);
    macros_ = stdlib.macros;
    defined_ = stdlib.defined;
    reported_recursion_ = stdlib.reported_recursion;
    hide_sets_ = stdlib.hide_sets;
    expanded_tokens_ = stdlib.expanded_tokens;
    input_tokens_ = stdlib.input_tokens;
    out_.pragmas = stdlib.pragmas;
    push_file(file, dir, sm_.path(file));
    return read_all();
  }

  // After run() on an empty file: what the stdlib left, for run_after().
  void keep_state(StdlibState& s) const {
    s.macros = macros_;
    s.defined = defined_;
    s.reported_recursion = reported_recursion_;
    s.hide_sets = hide_sets_;
    s.expanded_tokens = expanded_tokens_;
    s.input_tokens = input_tokens_;
  }

 private:
  Preprocessed read_all() {
    // Most programs come out about as long as they went in: room for that
    // at once, rather than copies of a growing list (untouched room costs
    // address space only).
    out_.tokens.reserve(input_tokens_ + 1);
    Stream main;
    main.reads_files = true;
    Token t;
    while (!aborted_ && pull(main, t, true)) {
      if (t.kind == TokenKind::Identifier && try_expand(main, t, 0)) continue;
      out_.tokens.push_back(std::move(t));
    }
    Token end;
    end.kind = TokenKind::End;
    end.line_start = true;
    end.span = last_span_;
    out_.tokens.push_back(end);
    out_.complete = !aborted_;
    for (const auto& [name, id] : defined_) {
      out_.macro_names.push_back(name);
      if (macros_[id].function_like && !macros_[id].statement) out_.function_macro_names.push_back(name);
    }
    out_.undefined_macros.assign(undefined_at_.begin(), undefined_at_.end());
    return std::move(out_);
  }

  const Options& opts_;
  SourceManager& sm_;
  Diagnostics& diags_;
  std::vector<Macro> macros_;                          // by id; ids are never reused
  MacroIds defined_;  // name -> id
  std::map<std::string, SourceSpan> undefined_at_;  // see Preprocessed::undefined_macros
  std::vector<OpenFile> files_;
  // The largest token list of a file already read, kept for the next file
  // to be lexed into (lex's `room`).
  std::vector<Token> spare_;
  std::vector<Cond> conds_;
  std::unordered_set<std::string> reported_recursion_;
  HideSets hide_sets_;
  std::size_t expanded_tokens_ = 0;
  std::size_t input_tokens_ = 0;
  // Argument tokens of the macro calls now being expanded, outermost to
  // innermost. F(F(F(...))) passes nearly all of its argument on at each
  // level, so this grows with the square of the nesting: it is checked at
  // each level before going deeper (kLiveArgumentBase, ...PerInputToken).
  std::size_t live_argument_tokens_ = 0;
  bool aborted_ = false;
  static constexpr int kMaxUnknownReported = 40;
  int unknown_reported_ = 0;
  SourceSpan last_span_;
  Preprocessed out_;

  // ------------------------------------------------------------ macros --

  void define_text(const std::string& name, const std::string& value, std::uint32_t file) {
    Macro m;
    m.name = name;
    // The body's tokens view the value: kept here, as the options holding
    // it may be gone when the macro is used (a cached stdlib state).
    m.body = lex(sm_.keep(value), file, diags_);
    m.body.pop_back();  // End
    for (auto& t : m.body) t.line_start = false;
    set_macro(std::move(m));
  }

  void define_builtins() {
    std::uint32_t cmd = sm_.add("<command line>", "");
    define_text("__RCX", "1", cmd);
    // nqc 3.1 defines its version as __NQC__ (301); programs written for it
    // test it to tell nqc from other compilers, and rcxc takes their nqc path.
    define_text("__NQC__", "301", cmd);
    define_text("__RCXC__", "1", cmd);
    // nqc defines until(c) before any file, with -n too: programs that test
    // for it, or define their own, see what they see with nqc.
    Macro until;
    until.name = "until";
    until.function_like = true;
    until.params = {"c"};
    until.statement = true;
    set_macro(std::move(until));
    for (const auto& [name, value] : opts_.defines) define_text(name, value, cmd);
    for (const auto& name : opts_.undefines) defined_.erase(name);
  }

  void set_macro(Macro m) {
    std::string name = m.name;
    macros_.push_back(std::move(m));
    defined_[name] = static_cast<std::uint32_t>(macros_.size() - 1);
    undefined_at_.erase(name);
  }

  const Macro* find_macro(std::string_view name) const {
    auto it = defined_.find(name);
    return it == defined_.end() ? nullptr : &macros_[it->second];
  }

  // ------------------------------------------------------------- files --

  void push_file(std::uint32_t file, const std::string& dir, const std::string& key) {
    OpenFile f;
    f.tokens = lex_deferring_stray(sm_.text(file), file, diags_, std::exchange(spare_, {}));
    input_tokens_ += f.tokens.size();
    // An #included file's tokens will mostly be output too: room for them
    // at once (read_all() makes room for the first files), so that a
    // program in included parts does not move its output into a list
    // growing one doubling at a time.
    if (input_tokens_ + 1 > out_.tokens.capacity())
      out_.tokens.reserve(std::max(input_tokens_ + 1, 2 * out_.tokens.capacity()));
    f.file = file;
    f.dir = dir;
    f.key = key;
    f.conds_at_entry = conds_.size();
    files_.push_back(std::move(f));
  }

  // Pops finished files; false when every file is done.
  bool current_file_token(Token*& t) {
    while (!files_.empty()) {
      OpenFile& f = files_.back();
      if (f.tokens[f.pos].kind != TokenKind::End) {
        t = &f.tokens[f.pos];
        return true;
      }
      // A comment never closed took the rest of the file: the program is
      // cut there, and the lexer's error is the one to give (nqc too).
      bool cut = f.tokens[f.pos].text == kEndInsideComment;
      for (std::size_t i = conds_.size(); i > f.conds_at_entry && !cut; --i)
        diags_.error(conds_[i - 1].span, "unterminated conditional directive (#endif missing)");
      conds_.resize(f.conds_at_entry);
      last_span_ = f.tokens[f.pos].span;
      if (f.tokens.capacity() > spare_.capacity()) spare_ = std::move(f.tokens);
      files_.pop_back();
      if (cut) {
        aborted_ = true;
        return false;
      }
    }
    return false;
  }

  bool active() const { return conds_.empty() || conds_.back().active; }

  // Next raw token of `s`. For the main stream, reads files: handles
  // directives (when `directives`) and skips inactive conditional text.
  bool pull(Stream& s, Token& out, bool directives) {
    if (!s.stack.empty()) {
      out = std::move(s.stack.back());
      s.stack.pop_back();
      return true;
    }
    if (!s.reads_files) return false;
    for (;;) {
      Token* t = nullptr;
      if (!current_file_token(t)) return false;
      // nqc reads a '#' anywhere in a line as a directive that runs to the
      // line's end (`x = 1; #define Y 2`, `r = 4; #endif`), skipped text
      // included; C only at the start of a line. A '#' inside a directive's
      // own line (`#define S(x) #x`) is that directive's.
      if (directives && t->is("#")) {
        directive();
        if (aborted_) return false;
        continue;
      }
      if (!active()) {
        ++files_.back().pos;
        continue;
      }
      if (t->kind == TokenKind::Unknown) report_unknown(*t);
      // A file's tokens are read once, front to back: each is moved out.
      out = std::move(*t);
      ++files_.back().pos;
      return true;
    }
  }

  // Is the next token of `s` a '(' (without consuming anything)?
  bool next_is_lparen(Stream& s) {
    if (!s.stack.empty()) return s.stack.back().is("(");
    if (!s.reads_files) return false;
    Token* t = nullptr;
    if (!current_file_token(t)) return false;
    if (t->is("#")) return false;
    return active() && t->is("(");
  }

  // The lexer leaves stray characters to be reported here, where the text
  // is not skipped. A file full of them is not NQC (a binary, say): stop
  // after a few dozen rather than one report per byte.
  void report_unknown(const Token& t) {
    report_unknown_token(t, diags_);
    if (++unknown_reported_ < kMaxUnknownReported) return;
    diags_.error(t.span, "too many invalid characters; is this an NQC source file?");
    aborted_ = true;
  }

  // The rest of the current directive line (tokens up to the next line start).
  std::vector<Token> line_tokens() {
    std::vector<Token> line;
    OpenFile& f = files_.back();
    while (f.tokens[f.pos].kind != TokenKind::End && !f.tokens[f.pos].line_start)
      line.push_back(std::move(f.tokens[f.pos++]));
    return line;
  }

  // ---------------------------------------------------------- expansion --

  // If `t` names a macro that may expand here, expands it onto `s`'s stack.
  bool try_expand(Stream& s, const Token& t, std::size_t depth) {
    auto it = defined_.find(t.text);
    if (it == defined_.end()) return false;
    std::uint32_t id = it->second;
    const Macro& m = macros_[id];
    if (m.statement) return false;
    // A function-like macro's name without a '(' after it is left as it is,
    // also inside its own expansion (`F(F)`), where it is no recursion.
    if (m.function_like && !next_is_lparen(s)) return false;
    if (hide_sets_.contains(t.hide, id)) {
      if (reported_recursion_.insert(m.name).second)
        diags_.error(t.span, "macro '" + m.name + "' is defined in terms of itself (recursive macros never end)");
      return false;
    }
    if (depth > kMaxExpansionDepth) {
      diags_.error(t.span, "macro expansion nested too deeply");
      aborted_ = true;
      return false;
    }
    std::vector<std::vector<Token>> args;
    std::uint32_t hide = t.hide;
    if (m.function_like) {
      Token rparen;
      if (!collect_args(s, t, m, args, rparen)) return true;
      if (args.size() != m.params.size() || !m.unusable.empty()) {
        report_unexpandable(t, rparen, m, args.size());
        // Inside an expression the call stands as a 0 the parser reads
        // past: `x = F(1);` is then the one error above, not a second
        // "expected an expression". Where a statement or declaration starts
        // (`MOVE(OUT_A);`, `DECL(x)` at the top), nothing stands there.
        if (!s.reads_files || (!out_.tokens.empty() && !starts_after(out_.tokens.back()))) {
          Token zero = t;
          zero.kind = TokenKind::Number;
          zero.text = "0";
          zero.span = {t.span.begin, rparen.span.end};
          s.stack.push_back(zero);
        }
        return true;
      }
      hide = hide_sets_.intersect(t.hide, rparen.hide);
    }
    std::size_t argument_tokens = 0;
    for (const auto& a : args) argument_tokens += a.size();
    if (live_argument_tokens_ + argument_tokens > kLiveArgumentBase + kLiveArgumentPerInputToken * input_tokens_) {
      diags_.error(t.span, "macro calls nested too deeply inside the arguments of '" + m.name + "'");
      aborted_ = true;
      return true;
    }
    live_argument_tokens_ += argument_tokens;
    hide = hide_sets_.with(hide, id);
    std::uint32_t exp = sm_.add_expansion({m.name, t.span});
    std::vector<Token> result = substitute(m, args, hide, exp, depth);
    for (const Token& r : result)  // from the body (see directive()), each use
      if (r.kind == TokenKind::Unknown && r.span.begin.expansion == exp) report_unknown(r);
    if (result.empty()) sm_.mark_expansion_empty(exp);
    live_argument_tokens_ -= argument_tokens;
    if (expanded_tokens_ > kExpansionBase + kExpansionPerInputToken * input_tokens_) {
      diags_.error(t.span, "macro expansion of '" + m.name + "' grows without bound");
      aborted_ = true;
      return true;
    }
    // The first token of an expansion takes the spacing of the macro name.
    if (!result.empty()) {
      result.front().space_before = t.space_before;
      result.front().line_start = false;
    }
    for (auto r = result.rbegin(); r != result.rend(); ++r) s.stack.push_back(std::move(*r));
    return true;
  }

  bool collect_args(Stream& s, const Token& name, const Macro& m, std::vector<std::vector<Token>>& args,
                    Token& rparen) {
    Token t;
    pull(s, t, false);  // '('
    args.emplace_back();
    int depth = 0;
    for (;;) {
      // Directives among the arguments are obeyed (`F(1,` then `#ifdef
      // LOUD` `2` `#else` `3` `#endif` `)`), as nqc and gcc obey them.
      if (!pull(s, t, true)) {
        if (aborted_) return false;
        diags_.error(name.span, "unterminated argument list invoking macro '" + m.name + "'");
        // The program's text ended inside the call: what the parser would
        // say of the end (an expression expected, a '{' not closed) is
        // about that one missing ')'.
        if (s.reads_files) aborted_ = true;
        return false;
      }
      if (t.is("(")) ++depth;
      if (t.is(")")) {
        if (depth == 0) break;
        --depth;
      }
      if (t.is(",") && depth == 0) {
        args.emplace_back();
        continue;
      }
      t.line_start = false;
      args.back().push_back(std::move(t));
    }
    rparen = t;
    // The tokens just taken leave their room behind in the stack: in
    // F(F(F(...))) every level's stack would keep the capacity of all that
    // the levels inside it took, a square of the nesting in memory.
    if (s.stack.capacity() > 4 * s.stack.size() + 256) s.stack.shrink_to_fit();
    // `F()` passes no argument to a macro without parameters.
    if (m.params.empty() && args.size() == 1 && args[0].empty()) args.clear();
    return true;
  }

  // Whether a statement or declaration may start after `t`.
  static bool starts_after(const Token& t) {
    return t.is(";") || t.is("{") || t.is("}") || t.is(")") || t.is(":") || t.is_identifier("else") ||
           t.is_identifier("do");
  }

  // A call of `m` with `given` arguments that cannot be expanded: the wrong
  // number of them, or a body that cannot be used. The error is read past.
  void report_unexpandable(const Token& name, const Token& rparen, const Macro& m, std::size_t given) {
    SourceSpan call{name.span.begin, rparen.span.end};
    if (given != m.params.size()) {
      auto& d = diags_.error(call, "macro '" + m.name + "' takes " + std::to_string(m.params.size()) + " argument" +
                                       (m.params.size() == 1 ? "" : "s") + ", but " + std::to_string(given) +
                                       (given == 1 ? " was" : " were") + " given");
      d.notes.push_back({m.span, "macro '" + m.name + "' is defined here"});
      d.parsed_past = true;
      return;
    }
    auto& d = diags_.error(call, "macro '" + m.name + "' cannot be used: " + m.unusable);
    d.notes.push_back({m.unusable_at, "in the definition of macro '" + m.name + "'"});
    d.parsed_past = true;
  }

  // Fully expands a token list on its own (a macro argument, an #if line).
  // `condition`: an #if line, where `defined NAME` and `defined(NAME)` are
  // 1 or 0 and NAME is not expanded, also where a macro's text brought the
  // `defined` in (`#define HAS_X defined(X)`, which nqc and C compilers take).
  std::vector<Token> expand_list(std::vector<Token> in, std::size_t depth, bool condition = false) {
    // Nothing to expand (a long #if line of numbers and operators): no copy.
    if (std::none_of(in.begin(), in.end(), [&](const Token& t) {
          return t.kind == TokenKind::Identifier && (defined_.count(t.text) != 0 || (condition && t.text == "defined"));
        }))
      return in;
    Stream s;
    std::reverse(in.begin(), in.end());
    s.stack = std::move(in);
    std::vector<Token> out;
    Token t;
    while (!aborted_ && pull(s, t, false)) {
      if (condition && t.is_identifier("defined")) {
        if (!defined_operator(s, t)) return {};
        out.push_back(std::move(t));
        continue;
      }
      if (t.kind == TokenKind::Identifier && try_expand(s, t, depth + 1)) continue;
      out.push_back(std::move(t));
    }
    return out;
  }

  // Turns `defined` (in `t`) and the operand it takes from `s` into the
  // number 1 or 0; false after an error.
  bool defined_operator(Stream& s, Token& t) {
    Token name, close;
    bool paren = false;
    bool got = pull(s, name, false);
    if (got && name.is("(")) {
      paren = true;
      got = pull(s, name, false);
    }
    if (!got || name.kind != TokenKind::Identifier || (paren && (!pull(s, close, false) || !close.is(")")))) {
      diags_.error(t.span, "'defined' needs a macro name: defined(NAME)");
      return false;
    }
    if (not_a_macro_name(name, "'defined'")) return false;
    t.kind = TokenKind::Number;
    t.text = find_macro(name.text) ? "1" : "0";
    return true;
  }

  int param_index(const Macro& m, const Token& t) const {
    if (!m.function_like || t.kind != TokenKind::Identifier) return -1;
    for (std::size_t i = 0; i < m.params.size(); ++i)
      if (m.params[i] == t.text) return static_cast<int>(i);
    return -1;
  }

  Token stringize(const std::vector<Token>& arg, const Token& hash) {
    Token t;
    t.kind = TokenKind::String;
    t.span = hash.span;
    std::string raw = spell(arg);
    std::string text = "\"";
    for (char c : raw) {
      if (c == '"' || c == '\\') text += '\\';
      text += c;
    }
    text += '"';
    t.text = sm_.keep(std::move(text));
    return t;
  }

  // Joins two tokens with ##; the result must lex as exactly one token.
  Token paste(const Token& a, const Token& b) {
    std::string_view text = sm_.keep(std::string(a.text) + std::string(b.text));
    Diagnostics scratch;
    auto toks = lex(text, a.span.begin.file, scratch);
    Token t = a;
    t.text = text;
    if (toks.size() != 2 || scratch.has_errors()) {
      diags_.error(a.span, "pasting '" + std::string(a.text) + "' and '" + std::string(b.text) + "' does not give a valid token");
      return t;
    }
    t.kind = toks[0].kind;
    return t;
  }

  std::vector<Token> substitute(const Macro& m, std::vector<std::vector<Token>>& args, std::uint32_t hide,
                                std::uint32_t exp, std::size_t depth) {
    // Pass 1: each body token becomes a segment; parameters next to ## stay
    // unexpanded, other parameters are fully expanded first (as in C).
    struct Segment {
      std::vector<Token> toks;
      bool paste = false;  // a ## operator
    };
    std::vector<Segment> segs;
    const auto& body = m.body;
    // Most bodies have no ##: their segments would only be joined in order,
    // so they go straight to the output instead (a vector per body token
    // was most of what expanding OUT_A cost).
    bool pastes = false;
    for (std::size_t i = 1; i + 1 < body.size() && !pastes; ++i) pastes = body[i].is("##");
    std::vector<Token> out;
    auto emit = [&](std::vector<Token> toks) {
      if (pastes)
        segs.push_back({std::move(toks), false});
      else
        out.insert(out.end(), std::make_move_iterator(toks.begin()), std::make_move_iterator(toks.end()));
    };
    std::vector<bool> param_used(m.params.size(), false);
    // An argument the body names once, outside # and ##, is expanded in
    // place rather than copied first: nested calls then hold each token
    // once instead of once per level.
    std::vector<int> param_uses(m.params.size(), 0);
    for (std::size_t i = 0; i < body.size(); ++i)
      if (int p = param_index(m, body[i]); p >= 0) {
        bool special = (i > 0 && (body[i - 1].is("##") || body[i - 1].is("#"))) ||
                       (i + 1 < body.size() && body[i + 1].is("##"));
        param_uses[static_cast<std::size_t>(p)] += special ? 2 : 1;
      }
    for (std::size_t i = 0; i < body.size(); ++i) {
      const Token& t = body[i];
      if (t.is("##") && i > 0 && i + 1 < body.size()) {
        segs.push_back({{}, true});
        continue;
      }
      if (m.function_like && t.is("#") && i + 1 < body.size() && param_index(m, body[i + 1]) >= 0) {
        Token str = stringize(args[static_cast<std::size_t>(param_index(m, body[i + 1]))], t);
        str.span.begin.expansion = str.span.end.expansion = exp;
        str.space_before = t.space_before;
        if (pastes)
          segs.push_back({{str}, false});
        else
          out.push_back(std::move(str));
        ++i;
        continue;
      }
      int p = param_index(m, t);
      if (p >= 0) {
        bool near_paste = (i > 0 && body[i - 1].is("##")) || (i + 1 < body.size() && body[i + 1].is("##"));
        auto& arg = args[static_cast<std::size_t>(p)];
        std::vector<Token> toks =
            near_paste ? arg : expand_list(param_uses[static_cast<std::size_t>(p)] == 1 ? std::move(arg) : arg, depth);
        // Growth is what the body adds: its own tokens, and an argument's
        // tokens each time it is used again (F(x) x x doubles its input).
        if (param_used[static_cast<std::size_t>(p)]) expanded_tokens_ += toks.size();
        param_used[static_cast<std::size_t>(p)] = true;
        if (!toks.empty()) toks.front().space_before = t.space_before;
        emit(std::move(toks));
        continue;
      }
      Token copy = t;
      ++expanded_tokens_;
      copy.span.begin.expansion = copy.span.end.expansion = exp;
      if (pastes)
        segs.push_back({{copy}, false});
      else
        out.push_back(std::move(copy));
    }
    // Pass 2: apply ## between neighbouring segments (an empty side pastes
    // to nothing, like C's placemarkers).
    bool paste_next = false;
    bool last_empty = true;
    for (auto& seg : segs) {
      if (seg.paste) {
        paste_next = true;
        continue;
      }
      if (paste_next && !last_empty && !seg.toks.empty()) {
        out.back() = paste(out.back(), seg.toks.front());
        out.insert(out.end(), std::make_move_iterator(seg.toks.begin() + 1), std::make_move_iterator(seg.toks.end()));
      } else {
        out.insert(out.end(), std::make_move_iterator(seg.toks.begin()), std::make_move_iterator(seg.toks.end()));
      }
      last_empty = seg.toks.empty() && (paste_next ? last_empty : true);
      paste_next = false;
    }
    for (auto& t : out) t.hide = hide_sets_.unite(t.hide, hide);
    return out;
  }

  // --------------------------------------------------------- directives --

  void directive() {
    OpenFile& f = files_.back();
    Token hash = std::move(f.tokens[f.pos++]);
    std::vector<Token> line = line_tokens();
    if (line.empty()) return;  // the null directive
    const Token& name = line[0];
    std::string_view d = name.text;
    if (d == "if" || d == "ifdef" || d == "ifndef") return begin_if(d, line, hash);  // may consume `line`
    if (d == "elif") return do_elif(line, hash);  // may consume `line`
    if (d == "else") return do_else(line, hash);
    if (d == "endif") return do_endif(line, hash);
    if (!active()) return;
    // A #define's body is compiled where the macro is used, so what it
    // holds that starts no token (`#define S "abc`, never closed) is
    // reported there (try_expand), as nqc compiles a program that never
    // uses it; the text of #error, #warning and #pragma is a message
    // (`#warning it's slow`), and an #if expression says what it cannot read.
    if (d == "define") return do_define(line);
    if (d == "undef") return do_undef(line);
    if (d == "include") return do_include(line, hash);
    if (d == "error") {
      diags_.error({hash.span.begin, line.back().span.end}, "#error " + spell(line, 1));
      return;
    }
    if (d == "warning") {
      diags_.warning({hash.span.begin, line.back().span.end}, WarningKind::WarningDirective,
                     "#warning " + spell(line, 1));
      return;
    }
    if (d == "pragma") return do_pragma(line);
    diags_.error(name.span, "unknown preprocessor directive '#" + std::string(d) + "'");
  }

  void extra_tokens(const std::vector<Token>& line, std::size_t from) {
    if (line.size() > from)
      diags_.warning(span_of(line, from, line[0].span), WarningKind::ExtraTokens,
                     "extra tokens after #" + std::string(line[0].text) + " are ignored");
  }

  // nqc's lexer takes its keywords and reserved words before its
  // preprocessor sees them, so none is a macro name there ("#define
  // required a symbol name"): a program that used one would not compile
  // with nqc. True after saying so at `name`.
  bool not_a_macro_name(const Token& name, std::string_view what) {
    const char* why = frontend::not_a_macro_name(name.text);
    if (!why) return false;
    std::string said = why == std::string_view("a keyword") ? "is a keyword" : "is reserved by nqc (" + std::string(why) + ")";
    diags_.error(name.span, std::string(what) + " needs a macro name: '" + std::string(name.text) + "' " + said);
    return true;
  }

  void begin_if(std::string_view d, std::vector<Token>& line, const Token& hash) {
    Cond c;
    c.parent_active = active();
    c.span = {hash.span.begin, line[0].span.end};
    bool value = false;
    if (c.parent_active) {
      if (d == "if") {
        value = eval_condition(line);
      } else if (line.size() < 2 || line[1].kind != TokenKind::Identifier) {
        diags_.error(line.size() < 2 ? line[0].span : line[1].span, "#" + std::string(d) + " needs a macro name");
      } else if (!not_a_macro_name(line[1], "#" + std::string(d))) {
        value = (find_macro(line[1].text) != nullptr) == (d == "ifdef");
        extra_tokens(line, 2);
      }
    }
    c.active = c.parent_active && value;
    c.taken = c.active;
    conds_.push_back(c);
  }

  bool check_open_group(const std::vector<Token>& line) {
    if (conds_.size() <= files_.back().conds_at_entry) {
      diags_.error(line[0].span, "#" + std::string(line[0].text) + " without #if");
      return false;
    }
    if (conds_.back().seen_else) {
      auto& e = diags_.error(line[0].span, "#" + std::string(line[0].text) + " after #else");
      e.notes.push_back({conds_.back().span, "the conditional started here"});
      return false;
    }
    return true;
  }

  void do_elif(std::vector<Token>& line, const Token&) {
    if (!check_open_group(line)) return;
    Cond& c = conds_.back();
    if (!c.parent_active || c.taken) {
      c.active = false;
      return;
    }
    c.active = eval_condition(line);
    c.taken = c.active;
  }

  void do_else(const std::vector<Token>& line, const Token&) {
    if (!check_open_group(line)) return;
    Cond& c = conds_.back();
    c.seen_else = true;
    c.active = c.parent_active && !c.taken;
    c.taken = true;
    extra_tokens(line, 1);
  }

  void do_endif(const std::vector<Token>& line, const Token&) {
    if (conds_.size() <= files_.back().conds_at_entry) {
      diags_.error(line[0].span, "#endif without #if");
      return;
    }
    conds_.pop_back();
    if (active()) extra_tokens(line, 1);
  }

  void do_define(const std::vector<Token>& line) {
    if (line.size() < 2 || line[1].kind != TokenKind::Identifier) {
      diags_.error(line.size() < 2 ? line[0].span : line[1].span, "#define needs a macro name");
      return;
    }
    Macro m;
    m.name = line[1].text;
    m.span = line[1].span;
    if (m.name == "defined") {
      diags_.error(line[1].span, "'defined' cannot be used as a macro name");
      return;
    }
    if (not_a_macro_name(line[1], "#define")) return;
    std::size_t i = 2;
    if (i < line.size() && line[i].is("(") && !line[i].space_before) {
      m.function_like = true;
      ++i;
      bool ok = false;
      if (i < line.size() && line[i].is(")")) {
        ok = true;
        ++i;
      }
      while (!ok && i < line.size()) {
        if (line[i].kind != TokenKind::Identifier) break;
        // nqc takes such a macro and substitutes the first parameter of the
        // name (param_index finds the first); so does rcxc, with a warning.
        if (std::find(m.params.begin(), m.params.end(), line[i].text) != m.params.end())
          diags_.warning(line[i].span, WarningKind::MacroDefinition,
                         "duplicate macro parameter '" + std::string(line[i].text) +
                             "': its uses take the first one's argument, as in nqc");
        m.params.emplace_back(line[i].text);
        ++i;
        if (i < line.size() && line[i].is(")")) {
          ok = true;
          ++i;
        } else if (i < line.size() && line[i].is(",")) {
          ++i;
        } else {
          break;
        }
      }
      // nqc defines nothing then and says nothing; a use of the name
      // fails later ("undefined variable"). A warning says why.
      if (!ok) {
        diags_.warning(i < line.size() ? line[i].span : line.back().span, WarningKind::MacroDefinition,
                       "expected a parameter name or ')' in the parameter list of macro '" + m.name +
                           "': the #define is ignored");
        return;
      }
    }
    m.body.assign(line.begin() + static_cast<std::ptrdiff_t>(i), line.end());
    if (!m.body.empty()) m.body.front().space_before = false;
    for (std::size_t k = 0; k < m.body.size(); ++k) {
      bool edge = k == 0 || k + 1 == m.body.size();
      std::string why;
      if (m.body[k].is("##") && edge) why = "'##' cannot appear at either end of a macro body";
      if (m.function_like && m.body[k].is("#") && (k + 1 == m.body.size() || param_index(m, m.body[k + 1]) < 0))
        why = "'#' is not followed by a macro parameter";
      if (why.empty()) continue;
      if (!m.function_like) {
        diags_.error(m.body[k].span, why);
        return;
      }
      m.unusable = why;
      m.unusable_at = m.body[k].span;
      break;
    }
    if (const Macro* old = find_macro(m.name); old && old->statement) {
      diags_.warning(m.span, WarningKind::MacroRedefined,
                     "macro '" + m.name + "' redefined (nqc refuses this: it predefines " + m.name +
                         "(c) as while (!(c)))");
    } else if (old && !same_definition(*old, m)) {
      auto& w = diags_.warning(m.span, WarningKind::MacroRedefined, "macro '" + m.name + "' redefined");
      if (old->span.begin.valid()) w.notes.push_back({old->span, "the previous definition is here"});
    }
    set_macro(std::move(m));
  }

  static bool same_definition(const Macro& a, const Macro& b) {
    if (a.function_like != b.function_like || a.params != b.params || a.body.size() != b.body.size()) return false;
    for (std::size_t i = 0; i < a.body.size(); ++i)
      if (a.body[i].text != b.body[i].text || (i > 0 && a.body[i].space_before != b.body[i].space_before))
        return false;
    return true;
  }

  void do_undef(const std::vector<Token>& line) {
    if (line.size() < 2 || line[1].kind != TokenKind::Identifier) {
      diags_.error(line.size() < 2 ? line[0].span : line[1].span, "#undef needs a macro name");
      return;
    }
    if (not_a_macro_name(line[1], "#undef")) return;
    if (auto it = defined_.find(line[1].text); it != defined_.end()) {
      defined_.erase(it);
      undefined_at_[std::string(line[1].text)] = line[1].span;
    }
    extra_tokens(line, 2);
  }

  void do_include(const std::vector<Token>& line, const Token& hash) {
    std::vector<Token> rest(line.begin() + 1, line.end());
    if (!rest.empty() && rest[0].kind == TokenKind::Identifier) rest = expand_list(rest, 0);
    std::string name;
    if (!rest.empty() && rest[0].kind == TokenKind::String) {
      name = rest[0].text.substr(1, rest[0].text.size() - 2);
    } else if (!rest.empty() && rest[0].is("<") && rest.back().is(">") && rest.size() > 2) {
      for (std::size_t i = 1; i + 1 < rest.size(); ++i) name += rest[i].text;
    } else if (!rest.empty() && rest[0].kind == TokenKind::Unknown) {
      // `#include “rcx.nqh”`, pasted from a word processor: the quote's own
      // message says what to type.
      report_unknown(rest[0]);
      return;
    } else {
      diags_.error(line[0].span, "#include expects \"FILE\" or <FILE>");
      return;
    }
    SourceSpan where = {hash.span.begin, line.back().span.end};
    if (files_.size() >= kMaxIncludeDepth) {
      diags_.error(where, "#include nested too deeply (more than " + std::to_string(kMaxIncludeDepth) + " levels)");
      return;
    }
    // Search: the including file's folder, each -I folder, the current
    // folder, then the stdlib. nqc looks in the current folder (and -I)
    // only, so a header in a subfolder may include another by its path from
    // the folder nqc runs in (`#include "b.nqh"` inside `sub/a.nqh`, b.nqh
    // beside the program): last, so it only finds what the others do not.
    std::vector<std::string> dirs;
    if (!files_.back().dir.empty()) dirs.push_back(files_.back().dir);
    dirs.insert(dirs.end(), opts_.include_dirs.begin(), opts_.include_dirs.end());
    dirs.push_back(".");
    std::optional<fs::path> not_a_file;   // found, but a folder or a device
    std::optional<fs::path> broken_link;  // a link to nothing, or a loop of links
    for (const auto& d : dirs) {
      fs::path p = fs::path(d) / name;
      std::error_code ec;
      if (!fs::is_regular_file(p, ec)) {
        if (fs::exists(p, ec)) {
          if (!not_a_file) not_a_file = p;
        } else if (!broken_link && fs::is_symlink(fs::symlink_status(p, ec))) {
          broken_link = p;
        }
        continue;
      }
      auto file = rcx::read_file(p.string(), rcx::kSourceFile);
      if (opts_.unsaved) {  // rcxc lsp: a file open in the editor is read as typed
        auto typed = opts_.unsaved->find(fs::absolute(p, ec).lexically_normal().string());
        if (typed != opts_.unsaved->end()) file = typed->second;
      }
      if (auto* problem = std::get_if<rcx::FileProblem>(&file)) {
        if (*problem != rcx::FileProblem::TooLarge) continue;
        diags_.error(where, rcx::too_large_message(p.string(), rcx::kSourceFile));
        return;
      }
      std::string* text = &std::get<std::string>(file);
      if (std::string why = not_source_reason(p.string(), *text); !why.empty()) {
        diags_.error(where, why);
        return;
      }
      std::string key = fs::weakly_canonical(p, ec).string();
      if (!enter_checked(key, where)) return;
      std::uint32_t id = sm_.add(p.lexically_normal().string(), std::move(*text));
      sm_.set_include_site(id, where);
      push_file(id, p.parent_path().string(), key);
      return;
    }
    if (auto text = stdlib::find(name)) {
      std::string key = "<stdlib>/" + name;
      if (!enter_checked(key, where)) return;
      std::uint32_t id = sm_.add(name, std::string(*text));
      sm_.mark_library(id);
      sm_.set_include_site(id, where);
      push_file(id, "", key);
      return;
    }
    if (not_a_file) {
      std::error_code ec;
      diags_.error(where, "cannot include '" + not_a_file->string() + "': it is " +
                              (fs::is_directory(*not_a_file, ec) ? "a folder" : "a device or special file") +
                              ", not a source file");
      return;
    }
    // In the words every other read of a user's file uses (rcx/file_read.h).
    if (broken_link) {
      diags_.error(where, "cannot include '" + broken_link->string() + "': it is " +
                              rcx::cannot_open_reason(broken_link->string()));
      return;
    }
    auto& e = diags_.error(where, "cannot find include file '" + name + "'");
    // A mistyped -I is taken without a word (as gcc takes it); here is
    // where it shows.
    for (const auto& d : opts_.include_dirs) {
      std::error_code ec;
      if (!fs::is_directory(d, ec))
        e.notes.push_back({{}, "-I " + d + (fs::exists(d, ec) ? " is a file, not a folder" : ": no such folder")});
    }
  }

  // False (with a diagnostic naming the chain) if `key` would be open a
  // third time. Files that include each other behind include guards open
  // each file at most twice (the second time the guard skips the body), so
  // only a cycle that nothing stops gets this far.
  bool enter_checked(const std::string& key, SourceSpan where) {
    int open = 0;
    for (const auto& f : files_) open += f.key == key;
    if (open < 2) return true;
    for (std::size_t i = 0; i < files_.size(); ++i) {
      if (files_[i].key != key) continue;
      std::string chain;
      for (std::size_t j = i; j < files_.size(); ++j) chain += sm_.path(files_[j].file) + " -> ";
      chain += sm_.path(files_[i].file);
      // nqc reads such a file 16 deep and then skips the #include without a
      // word, so one that declares nothing compiles; anything else it holds
      // is declared again, 15 times over. Nothing is meant by it: a guard is.
      diags_.error(where, "#include cycle: " + chain + ": a file that may be included again needs an include guard "
                          "('#ifndef NAME' and '#define NAME' at its top, '#endif' at its end)");
      return false;
    }
    return true;
  }

  void do_pragma(const std::vector<Token>& line) {
    if (line.size() < 2) {
      diags_.warning(line[0].span, WarningKind::Pragma, "empty #pragma ignored");
      return;
    }
    const Token& what = line[1];
    // Of `noinit` and `init NAME` the later holds, as in nqc: init after
    // noinit runs NAME, noinit after init runs nothing and names nothing.
    if (what.is_identifier("noinit")) {
      out_.pragmas.noinit = true;
      out_.pragmas.init.reset();
      extra_tokens(line, 2);
      return;
    }
    // A pragma nqc cannot read is a warning ("illegal #pragma") there and
    // changes nothing; so it is here, so that such a program still builds.
    if (what.is_identifier("init")) {
      if (line.size() < 3 || line[2].kind != TokenKind::Identifier) {
        diags_.warning(what.span, WarningKind::Pragma,
                       "#pragma init needs the name of a sub or function; the #pragma is ignored");
        return;
      }
      out_.pragmas.noinit = false;
      out_.pragmas.init = line[2].text;
      out_.pragmas.init_span = line[2].span;
      extra_tokens(line, 3);
      return;
    }
    if (what.is_identifier("reserve")) {
      std::vector<Token> nums = expand_list(std::vector<Token>(line.begin() + 2, line.end()), 0);
      std::vector<std::int64_t> values;
      for (const auto& t : nums) {
        std::int64_t v = 0;
        if (t.is(",")) continue;
        if (!number_value(t, v)) {
          diags_.warning(t.span, WarningKind::Pragma,
                         "#pragma reserve expects numbers: #pragma reserve LO [HI]; the #pragma is ignored");
          return;
        }
        values.push_back(v);
      }
      if (values.empty()) {
        diags_.warning(what.span, WarningKind::Pragma,
                       "#pragma reserve expects one or two slot numbers: #pragma reserve LO [HI]; the #pragma is ignored");
        return;
      }
      if (values.size() > 2) {
        // nqc reserves the first two and says nothing of the rest.
        diags_.warning(what.span, WarningKind::Pragma,
                       "#pragma reserve takes at most two slot numbers: the ones after " +
                           std::to_string(values[1]) + " are ignored");
        values.resize(2);
      }
      std::int64_t lo = values[0], hi = values.size() == 2 ? values[1] : values[0];
      if (lo < 0 || hi > 31 || lo > hi) {
        diags_.error(span_of(line, 2, what.span), "#pragma reserve range " + std::to_string(lo) + ".." +
                                                    std::to_string(hi) + " is not within variable slots 0..31");
        return;
      }
      out_.pragmas.reserve.push_back({static_cast<int>(lo), static_cast<int>(hi), span_of(line, 0, what.span)});
      return;
    }
    diags_.warning(what.span, WarningKind::Pragma, "unknown #pragma '" + std::string(what.text) + "' ignored");
  }

  // ------------------------------------------------------ #if evaluation --

  // Consumes `line` (the directive's tokens): the expression is made of
  // them in place, since a line can be most of a file's tokens.
  bool eval_condition(std::vector<Token>& line) {
    const Token directive = line[0];
    std::vector<Token> toks(std::make_move_iterator(line.begin() + 1), std::make_move_iterator(line.end()));
    line.clear();
    std::size_t before = diags_.error_count();
    toks = expand_list(std::move(toks), 0, true);
    if (diags_.error_count() != before) return false;
    if (toks.empty()) {
      diags_.error(directive.span, "#" + std::string(directive.text) + " needs an expression");
      return false;
    }
    CondEval ev{toks, diags_, *this, 0, false, 0, 0};
    std::int64_t v = ev.ternary();
    if (!ev.failed && ev.pos < toks.size()) ev.fail(toks[ev.pos], "unexpected '" + std::string(toks[ev.pos].text) + "' in #if expression");
    return !ev.failed && v != 0;
  }

  // A recursive-descent evaluator of #if expressions over 64-bit integers.
  // Its recursion is bounded by kMaxIfNesting (parentheses, prefix
  // operators and `?:` each nest), so no #if line can overflow the stack.
  struct CondEval {
    const std::vector<Token>& toks;
    Diagnostics& diags;
    const Preprocessor& pp;
    std::size_t pos;
    bool failed;
    int depth;
    // Above 0 inside an operand that C does not evaluate (the right of `0 &&`
    // and `1 ||`, the branch `?:` does not take): `#if 0 && (1 / 0)` is 0
    // there, as gcc has it, where a division by zero counted is an error.
    int unevaluated;

    // Counts one level while alive; false when the limit is passed (then
    // the evaluation has failed with a message at `at`).
    struct Nest {
      CondEval& ev;
      explicit Nest(CondEval& e) : ev(e) { ++ev.depth; }
      ~Nest() { --ev.depth; }
      bool ok(const Token& at) {
        if (ev.depth <= kMaxIfNesting) return true;
        ev.fail(at, "#if expression nested too deeply (more than " + std::to_string(kMaxIfNesting) + " levels)");
        return false;
      }
      Nest(const Nest&) = delete;
      Nest& operator=(const Nest&) = delete;
    };

    void fail(const Token& at, const std::string& msg) {
      if (!failed) diags.error(at.span, msg);
      failed = true;
    }
    bool accept(std::string_view p) {
      if (pos < toks.size() && toks[pos].is(p)) {
        ++pos;
        return true;
      }
      return false;
    }
    const Token& here() const { return pos < toks.size() ? toks[pos] : toks.back(); }

    std::int64_t ternary() {
      Nest nest(*this);
      if (!nest.ok(here()) || failed) return 0;
      std::int64_t c = binary(0);
      if (!accept("?")) return c;
      unevaluated += c ? 0 : 1;
      std::int64_t a = ternary();
      unevaluated -= c ? 0 : 1;
      if (!accept(":")) fail(here(), "expected ':' in #if expression");
      unevaluated += c ? 1 : 0;
      std::int64_t b = ternary();
      unevaluated -= c ? 1 : 0;
      return c ? a : b;
    }

    static int precedence(const Token& t) {
      if (t.kind != TokenKind::Punct) return -1;
      static const std::pair<std::string_view, int> table[] = {
          {"||", 1}, {"&&", 2}, {"|", 3}, {"^", 4}, {"&", 5}, {"==", 6}, {"!=", 6}, {"<", 7}, {"<=", 7},
          {">", 7}, {">=", 7}, {"<<", 8}, {">>", 8}, {"+", 9}, {"-", 9}, {"*", 10}, {"/", 10}, {"%", 10}};
      for (auto& [op, p] : table)
        if (t.text == op) return p;
      return -1;
    }

    std::int64_t binary(int min_prec) {
      std::int64_t lhs = unary();
      for (;;) {
        if (pos >= toks.size() || failed) return lhs;
        const Token& op = toks[pos];
        int p = precedence(op);
        if (p < 0 || p < min_prec) return lhs;
        ++pos;
        bool skipped = (op.text == "&&" && lhs == 0) || (op.text == "||" && lhs != 0);
        unevaluated += skipped ? 1 : 0;
        std::int64_t rhs = binary(p + 1);
        unevaluated -= skipped ? 1 : 0;
        lhs = apply(op, lhs, rhs);
      }
    }

    std::int64_t apply(const Token& op, std::int64_t a, std::int64_t b) {
      std::string_view o = op.text;
      if ((o == "/" || o == "%") && b == 0) {
        if (unevaluated == 0) fail(op, "division by zero in #if expression");
        return 0;
      }
      auto ua = static_cast<std::uint64_t>(a), ub = static_cast<std::uint64_t>(b);
      if (o == "||") return a || b;
      if (o == "&&") return a && b;
      if (o == "|") return a | b;
      if (o == "^") return a ^ b;
      if (o == "&") return a & b;
      if (o == "==") return a == b;
      if (o == "!=") return a != b;
      if (o == "<") return a < b;
      if (o == "<=") return a <= b;
      if (o == ">") return a > b;
      if (o == ">=") return a >= b;
      if (o == "<<") return static_cast<std::int64_t>(ua << (ub & 63));
      if (o == ">>") return a >> (ub & 63);
      if (o == "+") return static_cast<std::int64_t>(ua + ub);
      if (o == "-") return static_cast<std::int64_t>(ua - ub);
      if (o == "*") return static_cast<std::int64_t>(ua * ub);
      if (a == INT64_MIN && b == -1) return o == "/" ? a : 0;
      if (o == "/") return a / b;
      return a % b;
    }

    std::int64_t unary() {
      if (pos >= toks.size()) {
        fail(toks.back(), "#if expression ends too early");
        return 0;
      }
      const Token& t = toks[pos];
      Nest nest(*this);
      if (!nest.ok(t) || failed) return 0;
      if (accept("-")) return static_cast<std::int64_t>(0 - static_cast<std::uint64_t>(unary()));
      if (accept("+")) return unary();
      if (accept("!")) return !unary();
      if (accept("~")) return ~unary();
      if (accept("(")) {
        std::int64_t v = ternary();
        if (!accept(")")) fail(here(), "expected ')' in #if expression");
        return v;
      }
      ++pos;
      if (t.kind == TokenKind::Number || t.kind == TokenKind::Char) {
        std::int64_t v = 0;
        if (!number_value(t, v)) fail(t, invalid_number_message(t.text));
        return v;
      }
      // Counting these as 0 would hide that the preprocessor cannot know
      // them (nqc: syntax error).
      if (t.kind == TokenKind::Identifier && (t.text == "__taskid" || t.text == "__type")) {
        fail(t, std::string(t.text) + " is known only when the code is generated, not in #if");
        return 0;
      }
      if (t.kind == TokenKind::Identifier) return name_value(t);
      fail(t, "unexpected '" + std::string(t.text) + "' in #if expression");
      return 0;
    }

    // C counts a name left after expansion as 0. nqc refuses the names
    // that are a mistake there, and so does rcxc: a function-like macro
    // without its arguments (`#if DEBUG` meant `#ifdef DEBUG`; nqc: "wrong
    // number of arguments") and a keyword or reserved word (nqc: "syntax
    // error in expression"). `true` and `false` are keywords like the
    // others: C would count them as 0 (before C23), C++ as 1 and 0; the
    // error says which number to write.
    std::int64_t name_value(const Token& t) {
      std::string name(t.text);
      if (t.text == "true" || t.text == "false") {
        fail(t, "'" + name + "' is a keyword, not a value: #if takes numbers and macros; write " +
                    (t.text == "true" ? "1" : "0") + " (nqc refuses it too)");
        return 0;
      }
      if (const Macro* m = pp.find_macro(t.text); m && m->function_like) {
        fail(t, "'" + name + "' is a function-like macro: #if needs its arguments, '" + name +
                    "(...)'; to ask whether it is defined, write 'defined(" + name + ")'");
        return 0;
      }
      if (const char* why = frontend::not_a_macro_name(t.text)) {
        std::string said = why == std::string_view("a keyword") ? "a keyword"
                                                                 : "reserved by nqc (" + std::string(why) + ")";
        fail(t, "'" + name + "' is " + said + ", not a value: #if takes numbers and macros");
        return 0;
      }
      return 0;
    }
  };
};

}  // namespace

Preprocessed preprocess(std::uint32_t file, const std::string& dir, const Options& options, SourceManager& sm,
                        Diagnostics& diags) {
  Preprocessor pp(options, sm, diags);
  return pp.run(file, dir);
}

std::shared_ptr<const StdlibState> preprocess_stdlib(const Options& options) {
  if (options.no_stdlib) return nullptr;
  SourceManager sm;
  Diagnostics diags;
  std::uint32_t file = sm.add("<empty>", "");
  Preprocessor pp(options, sm, diags);
  Preprocessed out = pp.run(file, "");
  if (!diags.all().empty() || !out.complete) return nullptr;
  auto state = std::make_shared<StdlibState>();
  state->defines = options.defines;
  state->undefines = options.undefines;
  state->first_file = file + 1;
  for (std::uint32_t f = file + 1; f < sm.size(); ++f) state->files.push_back({sm.path(f), sm.text(f), sm.is_library(f)});
  for (std::uint32_t e = 1; e <= sm.expansion_count(); ++e) state->expansions.push_back(sm.expansion(e));
  pp.keep_state(*state);
  state->input_tokens -= 1;  // the empty file's End
  state->pragmas = std::move(out.pragmas);
  out.tokens.pop_back();     // End
  state->tokens = std::move(out.tokens);
  state->texts = std::move(sm);
  return state;
}

bool fits(const StdlibState& stdlib, const Options& options, const SourceManager& sm) {
  return !options.no_stdlib && options.defines == stdlib.defines && options.undefines == stdlib.undefines &&
         sm.size() == stdlib.first_file && sm.expansion_count() == 0;
}

const std::vector<Token>& stdlib_tokens(const StdlibState& stdlib) { return stdlib.tokens; }

Preprocessed preprocess_after_stdlib(const StdlibState& stdlib, std::uint32_t file, const std::string& dir,
                                     const Options& options, SourceManager& sm, Diagnostics& diags) {
  Preprocessor pp(options, sm, diags);
  return pp.run_after(stdlib, file, dir);
}

SourceLoc presumed_loc(const SourceLoc& loc, const SourceManager& sm) {
  SourceLoc l = loc;
  for (int guard = 0; l.expansion != 0 && guard < 256; ++guard) l = sm.expansion(l.expansion).site.begin;
  return l;
}

std::string tokens_to_text(const std::vector<Token>& tokens, const SourceManager& sm) {
  std::string out;
  std::uint32_t file = UINT32_MAX;
  std::uint32_t line = 0;
  for (const auto& t : tokens) {
    if (t.kind == TokenKind::End) break;
    SourceLoc at = presumed_loc(t.span.begin, sm);
    if (at.file != file || at.line < line || at.line > line + 8) {
      if (!out.empty()) out += '\n';
      out += "# " + std::to_string(at.line) + " \"" + sm.path(at.file) + "\"\n";
      file = at.file;
      line = at.line;
    } else if (at.line > line) {
      out.append(at.line - line, '\n');
      line = at.line;
    } else if (t.space_before) {
      out += ' ';
    }
    out += t.text;
  }
  out += '\n';
  return out;
}

std::string not_source_reason(const std::string& path, std::string_view text) {
  if (rcx::starts_as_image(text))
    return "'" + path + "' is an RCX image, not NQC source (rcxc run and rcxc disasm read images)";
  if (rcx::holds_binary_data(text))
    return "'" + path + "' is not NQC source: it holds binary data";
  return "";
}

}  // namespace rcxc::frontend
