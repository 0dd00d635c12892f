#include "lsp/index.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include "backend/compile.h"
#include "frontend/parse.h"
#include "frontend/preprocess.h"
#include "frontend/spelling.h"
#include "frontend/token.h"
#include "stdlib/stdlib.h"

namespace rcxc::lsp {
namespace {

Place place_of(const SourceLoc& loc) { return {loc.file, loc.line, loc.column}; }
Range range_of(const SourceSpan& span) { return {place_of(span.begin), place_of(span.end)}; }

std::string trim(std::string_view s) {
  auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return "";
  auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

bool is_define_line(std::string_view line) {
  std::string t = trim(line);
  if (!starts_with(t, "#")) return false;
  return starts_with(trim(std::string_view(t).substr(1)), "define");
}

// The `//` comment block right above line `line`. For a macro the block may
// sit above a run of #define lines (one comment for a group of constants).
// Section rules (`// ---- Outputs ----`) are headings, not documentation.
std::string doc_above(const SourceManager& sm, std::uint32_t file, std::uint32_t line, bool macro) {
  std::uint32_t l = line;
  if (macro)
    while (l > 1 && is_define_line(sm.line(file, l - 1))) --l;
  std::vector<std::string> lines;
  while (l > 1) {
    std::string t = trim(sm.line(file, l - 1));
    if (!starts_with(t, "//")) break;
    --l;
    std::string text = trim(std::string_view(t).substr(2));
    if (starts_with(text, "---")) break;
    lines.push_back(text);
  }
  std::reverse(lines.begin(), lines.end());
  std::string doc;
  for (const auto& s : lines) {
    if (!doc.empty()) doc += '\n';
    doc += s;
  }
  return doc;
}

std::string param_text(const ast::Param& p) {
  switch (p.kind) {
    case ast::ParamKind::Value: return "int " + p.name;
    case ast::ParamKind::Const: return "const int " + p.name;
    case ast::ParamKind::Reference: return "int &" + p.name;
    case ast::ParamKind::ConstReference: return "const int &" + p.name;
  }
  return p.name;
}

// The #define line (with its continuation lines) as written.
std::string define_text(const SourceManager& sm, std::uint32_t file, std::uint32_t line) {
  std::string text;
  for (std::uint32_t l = line; l < line + 20; ++l) {
    std::string part = trim(sm.line(file, l));
    bool more = !part.empty() && part.back() == '\\';
    if (more) part = trim(std::string_view(part).substr(0, part.size() - 1));
    if (!text.empty()) text += ' ';
    text += part;
    if (!more) break;
  }
  return text;
}

bool from_file(const SourceSpan& s) { return s.begin.valid() && s.begin.expansion == 0; }

struct Collector {
  const SourceManager& sm;
  std::vector<Definition>& defs;

  void add(std::string name, DefKind kind, const SourceSpan& span, std::string signature,
           std::optional<Range> scope = std::nullopt, std::string owner = "") {
    if (!from_file(span)) return;
    Definition d;
    d.name = std::move(name);
    d.kind = kind;
    d.at = range_of(span);
    d.extent = d.at;
    d.signature = std::move(signature);
    d.doc = doc_above(sm, span.begin.file, span.begin.line, false);
    d.scope = scope;
    d.owner = std::move(owner);
    defs.push_back(std::move(d));
  }

  void body(const ast::Stmt& s, const Range& scope, const std::string& owner) {
    std::visit(
        [&](const auto& n) {
          using T = std::decay_t<decltype(n)>;
          if constexpr (std::is_same_v<T, ast::Block>) {
            for (const auto& c : n.stmts) body(c, scope, owner);
          } else if constexpr (std::is_same_v<T, ast::DeclStmt>) {
            for (const auto& v : n.vars)
              add(v.name, DefKind::Local, v.span, "int " + v.name + "  // local in " + owner, scope, owner);
          } else if constexpr (std::is_same_v<T, ast::If>) {
            body(*n.then_branch, scope, owner);
            if (n.else_branch) body(**n.else_branch, scope, owner);
          } else if constexpr (std::is_same_v<T, ast::For>) {
            if (n.init) body(**n.init, scope, owner);
            body(*n.body, scope, owner);
          } else if constexpr (std::is_same_v<T, ast::Labeled>) {
            add(n.label, DefKind::Label, n.label_span, n.label + ":  // label in " + owner, scope, owner);
            body(*n.body, scope, owner);
          } else if constexpr (requires { n.body; }) {
            body(*n.body, scope, owner);
          }
        },
        s.node);
  }

  // The body's range becomes the extent of the definition just added (when
  // it was added: names spelled by a macro are not).
  Range extend_last(Range whole) {
    if (!defs.empty() && defs.back().at.begin.file == whole.begin.file && defs.back().at.begin.line == whole.begin.line &&
        defs.back().at.begin.column == whole.begin.column && whole.end.file == whole.begin.file)
      defs.back().extent = whole;
    return whole;
  }

  void program(const ast::Program& p) {
    for (const auto& g : p.globals) add(g.name, DefKind::Global, g.span, "int " + g.name);
    for (const auto& t : p.tasks) {
      add(t.name, DefKind::Task, t.span, "task " + t.name + "()");
      body(t.body, extend_last({place_of(t.span.begin), place_of(t.body.span.end)}), "task " + t.name);
    }
    for (const auto& s : p.subs) {
      add(s.name, DefKind::Sub, s.span, "sub " + s.name + "()");
      body(s.body, extend_last({place_of(s.span.begin), place_of(s.body.span.end)}), "sub " + s.name);
    }
    for (const auto& f : p.functions) {
      std::string sig = "void " + f.name + "(";
      for (std::size_t i = 0; i < f.params.size(); ++i) sig += (i ? ", " : "") + param_text(f.params[i]);
      add(f.name, DefKind::Function, f.span, sig + ")");
      Range scope = extend_last({place_of(f.span.begin), place_of(f.body.span.end)});
      for (const auto& prm : f.params)
        add(prm.name, DefKind::Param, prm.span, param_text(prm) + "  // parameter of " + f.name, scope, f.name);
      body(f.body, scope, "function " + f.name);
    }
  }
};

// Where the program assigns a name or passes it whole to a call, from the
// lenient parse's tree. Names a macro spells are placed in its body.
struct AccessCollector {
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, Index::Accessed>& out;

  void mark(const ast::Expr& e, Access a) {
    if (!std::holds_alternative<ast::Name>(e.node) || !e.span.begin.valid() || e.span.end.file != e.span.begin.file)
      return;
    auto& slot = out[{e.span.begin.file, e.span.begin.line, e.span.begin.column}];
    slot.end_line = e.span.end.line;
    slot.end_column = e.span.end.column;
    slot.access = std::max(slot.access, a);  // a name a macro uses twice is written if either use writes it
  }

  void expr(const ast::Expr& e) {
    std::visit(
        [&](const auto& n) {
          using T = std::decay_t<decltype(n)>;
          if constexpr (std::is_same_v<T, ast::Assign>) {
            mark(*n.target, Access::Write);
            expr(*n.target);
            expr(*n.value);
          } else if constexpr (std::is_same_v<T, ast::Unary>) {
            bool steps = n.op == ast::UnaryOp::PreInc || n.op == ast::UnaryOp::PreDec ||
                         n.op == ast::UnaryOp::PostInc || n.op == ast::UnaryOp::PostDec;
            if (steps) mark(*n.operand, Access::Write);
            expr(*n.operand);
          } else if constexpr (std::is_same_v<T, ast::Binary>) {
            expr(*n.lhs);
            expr(*n.rhs);
          } else if constexpr (std::is_same_v<T, ast::Conditional>) {
            expr(*n.cond);
            expr(*n.then_value);
            expr(*n.else_value);
          } else if constexpr (std::is_same_v<T, ast::Call>) {
            for (const auto& a : n.args) {
              mark(a, Access::Argument);
              expr(a);
            }
          } else if constexpr (std::is_same_v<T, ast::Source>) {
            expr(*n.type);
            expr(*n.arg);
          } else if constexpr (std::is_same_v<T, ast::SourceArg>) {
            expr(*n.operand);
          }
        },
        e.node);
  }

  void stmt(const ast::Stmt& s) {
    std::visit(
        [&](const auto& n) {
          using T = std::decay_t<decltype(n)>;
          if constexpr (std::is_same_v<T, ast::Block>) {
            for (const auto& c : n.stmts) stmt(c);
          } else if constexpr (std::is_same_v<T, ast::DeclStmt>) {
            for (const auto& v : n.vars)
              if (v.init) expr(*v.init);
          } else if constexpr (std::is_same_v<T, ast::ExprStmt>) {
            expr(n.expr);
          } else if constexpr (std::is_same_v<T, ast::If>) {
            expr(n.cond);
            stmt(*n.then_branch);
            if (n.else_branch) stmt(**n.else_branch);
          } else if constexpr (std::is_same_v<T, ast::For>) {
            if (n.init) stmt(**n.init);
            if (n.cond) expr(*n.cond);
            if (n.step) expr(*n.step);
            stmt(*n.body);
          } else if constexpr (std::is_same_v<T, ast::Asm>) {
            for (const auto& item : n.items) {
              if (const auto* b = std::get_if<ast::AsmByte>(&item)) expr(b->value);
              if (const auto* i = std::get_if<ast::AsmInstr>(&item))
                for (const auto& o : i->operands) expr(o);
            }
          } else {
            if constexpr (requires { n.cond; }) expr(n.cond);
            if constexpr (requires { n.count; }) expr(n.count);
            if constexpr (requires { n.value; }) expr(n.value);
            if constexpr (requires { n.body; }) stmt(*n.body);
          }
        },
        s.node);
  }

  void program(const ast::Program& p) {
    for (const auto& g : p.globals)
      if (g.init) expr(*g.init);
    for (const auto& t : p.tasks) stmt(t.body);
    for (const auto& s : p.subs) stmt(s.body);
    for (const auto& f : p.functions) stmt(f.body);
  }
};

// The `-D` options as macros of the index, in a file of their own (`-D
// NAME=VALUE` a line). They come after the files' macros, so a program's
// own #define of the name is the one found; an -U drops the name, and of
// two -D of one name the last counts, as in the preprocessor.
void add_command_line(Index& index, const frontend::Options& options) {
  std::vector<std::pair<std::string, std::string>> defines;
  for (const auto& d : options.defines) {
    std::erase_if(defines, [&](const auto& e) { return e.first == d.first; });
    if (std::find(options.undefines.begin(), options.undefines.end(), d.first) == options.undefines.end())
      defines.push_back(d);
  }
  std::string text;
  for (const auto& [name, value] : defines) text += "-D " + name + "=" + value + "\n";
  std::uint32_t file = index.sm.add("<command line>", text);
  index.command_line = file;
  index.is_stdlib.push_back(false);
  std::uint32_t line = 1;
  for (const auto& [name, value] : defines) {
    Definition d;
    d.name = name;
    d.kind = DefKind::Macro;
    d.at = {{file, line, 4}, {file, line, static_cast<std::uint32_t>(4 + name.size())}};
    d.extent = d.at;
    d.signature = "-D " + name + "=" + value;
    index.defs.push_back(std::move(d));
    ++line;
  }
}

// The characters of more than one byte in `text`, line by line, each
// decoded from its lead byte as utf16_column counts them.
std::vector<WideChar> wide_chars_of(std::string_view text) {
  std::vector<WideChar> out;
  std::uint32_t line = 1;
  for (std::size_t line_start = 0; line_start <= text.size(); ++line) {
    std::size_t end = std::min(text.find('\n', line_start), text.size());
    std::uint32_t units = 0;
    for (std::size_t i = line_start; i < end;) {
      std::size_t n = utf8_length(static_cast<unsigned char>(text[i]));
      units += n == 4 ? 2 : 1;
      if (n > 1)
        out.push_back({line, static_cast<std::uint32_t>(i - line_start), static_cast<std::uint32_t>(i - line_start + n),
                       units});
      i += n;
    }
    line_start = end + 1;
  }
  return out;
}

// Macros and identifier occurrences, read from each file's own tokens.
void scan_file(Index& index, std::uint32_t file) {
  Diagnostics ignored;
  std::vector<frontend::Token> tokens = frontend::lex(index.sm.text(file), file, ignored);
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const auto& t = tokens[i];
    if (t.kind != frontend::TokenKind::Identifier) continue;
    index.occurrences.push_back({std::string(t.text), range_of(t.span)});
    bool directive = i >= 2 && tokens[i - 2].line_start && tokens[i - 2].is("#") &&
                     tokens[i - 1].is_identifier("define") && !t.line_start;
    if (!directive) continue;
    Definition d;
    d.name = t.text;
    d.kind = DefKind::Macro;
    d.at = range_of(t.span);
    d.extent = d.at;
    d.signature = define_text(index.sm, file, t.span.begin.line);
    d.doc = doc_above(index.sm, file, t.span.begin.line, true);
    index.defs.push_back(std::move(d));
  }
}

SourceSpan outside_macros(SourceSpan span, const SourceManager& sm) {
  for (int guard = 0; span.begin.expansion != 0 && guard < 1000; ++guard) span = sm.expansion(span.begin.expansion).site;
  return span;
}

DocDiagnostic::Related related_of(const Note& n, const SourceManager& sm) {
  DocDiagnostic::Related r;
  r.message = n.message;
  SourceSpan s = outside_macros(n.span, sm);
  if (!s.begin.valid()) return r;
  r.path = sm.path(s.begin.file);
  r.line = s.begin.line;
  r.column = s.begin.column;
  bool end_ok = s.end.valid() && s.end.file == s.begin.file && before(place_of(s.begin), place_of(s.end));
  r.end_line = end_ok ? s.end.line : s.begin.line;
  r.end_column = end_ok ? s.end.column : s.begin.column + 1;
  return r;
}

// The compiler's diagnostics, each placed in the document: an included
// file's problem at its #include line, in the standard library's at the top.
std::vector<DocDiagnostic> compile_diagnostics(const std::string& path, const std::string& text,
                                               const frontend::Options& options, const WarningPolicy& warnings) {
  SourceManager sm;
  Diagnostics diags;
  diags.policy = warnings;
  // The whole compiler at the default level, not the frontend alone: the
  // editor shows what `rcxc compile` says, the passes' warnings (a sensor
  // never set up, a local read before it is written) and the back end's
  // errors (no variable slot left, a program too large) included.
  ir::Log log;
  backend::compile_source(path, text, options, ir::OptLevel::O2, sm, diags, log);
  std::vector<DocDiagnostic> out;
  const std::uint32_t main = 0;  // parse_source adds the document first
  for (const auto& d : diags.all()) {
    DocDiagnostic dd;
    dd.severity = d.severity;
    dd.message = d.message;
    dd.warning = d.warning;
    SourceSpan span = outside_macros(d.span, sm);
    if (span.begin.valid() && span.begin.file != main) {
      dd.related.push_back(related_of({span, d.message}, sm));
      SourceSpan site{};
      for (const auto& n : sm.include_notes(span.begin))
        if (n.span.begin.file == main) site = n.span;
      dd.message = "in " + std::filesystem::path(sm.path(span.begin.file)).filename().string() + ":" +
                   std::to_string(span.begin.line) + ": " + d.message;
      span = site;
    }
    if (span.begin.valid()) {
      dd.line = span.begin.line;
      dd.column = span.begin.column;
      bool end_ok = span.end.valid() && span.end.file == span.begin.file &&
                    before(place_of(span.begin), place_of(span.end));
      dd.end_line = end_ok ? span.end.line : span.begin.line;
      dd.end_column = end_ok ? span.end.column : span.begin.column + 1;
    }
    for (const auto& n : d.notes) dd.related.push_back(related_of(n, sm));
    out.push_back(std::move(dd));
  }
  return out;
}

}  // namespace

std::string_view def_kind_name(DefKind k) {
  switch (k) {
    case DefKind::Task: return "task";
    case DefKind::Sub: return "sub";
    case DefKind::Function: return "function";
    case DefKind::Global: return "global variable";
    case DefKind::Local: return "local variable";
    case DefKind::Param: return "parameter";
    case DefKind::Label: return "label";
    case DefKind::Macro: return "macro";
  }
  return "name";
}

Index build_index(const std::string& path, const std::string& text, const frontend::Options& options,
                  const WarningPolicy& warnings) {
  Index index;
  if (text.size() > kMaxDocument) {
    // The compiler's work and memory grow with the text (a 1 MiB document
    // took 6 s and 470 MB per change), and the protocol would allow 64 MiB.
    index.main_file = index.sm.add(path, text);
    index.is_stdlib.push_back(false);
    DocDiagnostic d;
    d.line = d.end_line = d.column = 1;
    d.end_column = 2;
    d.message = "the document is larger than a source file may be (" + std::to_string(kMaxDocument >> 20) +
                " MiB); it is not compiled, as rcxc compile would refuse it";
    index.diagnostics.push_back(std::move(d));
    return index;
  }
  index.diagnostics = compile_diagnostics(path, text, options, warnings);

  Diagnostics ignored;
  index.main_file = index.sm.add(path, text);
  std::string dir = std::filesystem::path(path).parent_path().string();
  frontend::Preprocessed pp = frontend::preprocess(index.main_file, dir.empty() ? "." : dir, options, index.sm, ignored);
  ast::Program program = frontend::parse_tokens(pp.tokens, ignored);
  Collector{index.sm, index.defs}.program(program);
  AccessCollector{index.accesses}.program(program);

  for (std::uint32_t f = 0; f < index.sm.size(); ++f) {
    auto embedded = stdlib::find(index.sm.path(f));
    index.is_stdlib.push_back(embedded && *embedded == index.sm.text(f));
    scan_file(index, f);
  }
  add_command_line(index, options);
  for (std::uint32_t f = 0; f < index.sm.size(); ++f) index.wide_chars.push_back(wide_chars_of(index.sm.text(f)));
  return index;
}

const Occurrence* occurrence_at(const Index& index, std::uint32_t file, std::uint32_t line, std::uint32_t column) {
  Place p{file, line, column};
  for (const auto& o : index.occurrences)
    if (contains(o.at, p) || o.at.end == p) return &o;
  return nullptr;
}

namespace {

// resolve among `named`, the definitions of one name.
const Definition* resolve_among(const std::vector<const Definition*>& named, const Place& where) {
  const Definition* macro = nullptr;
  const Definition* local = nullptr;
  const Definition* top = nullptr;
  for (const Definition* p : named) {
    const Definition& d = *p;
    if (contains(d.at, where)) return &d;
    if (d.kind == DefKind::Macro) {
      if (!macro) macro = &d;
    } else if (d.scope) {
      if (!contains(*d.scope, where)) continue;
      // The innermost scope; within one, the last declaration before the use.
      if (!local || before(local->scope->begin, d.scope->begin) ||
          (!before(d.scope->begin, local->scope->begin) && before(d.at.begin, where)))
        local = &d;
    } else if (!top) {
      top = &d;
    }
  }
  if (macro) return macro;
  return local ? local : top;
}

std::vector<const Definition*> named(const Index& index, const std::string& name) {
  std::vector<const Definition*> out;
  for (const auto& d : index.defs)
    if (d.name == name) out.push_back(&d);
  return out;
}

}  // namespace

const Definition* resolve(const Index& index, const std::string& name, const Place& where) {
  return resolve_among(named(index, name), where);
}

Access access_at(const Index& index, const Place& at) {
  // The last marked expression beginning at or before `at`, if it reaches past it.
  auto it = index.accesses.upper_bound({at.file, at.line, at.column});
  if (it == index.accesses.begin()) return Access::Read;
  --it;
  const std::uint32_t file = std::get<0>(it->first);
  const Index::Accessed& a = it->second;
  bool reaches = file == at.file && before(at, Place{file, a.end_line, a.end_column});
  return reaches ? a.access : Access::Read;
}

namespace {

bool scope_before(const Definition* a, const Definition* b) {
  return std::tuple(a->scope->begin.file, a->scope->begin.line, a->scope->begin.column) <
         std::tuple(b->scope->begin.file, b->scope->begin.line, b->scope->begin.column);
}

// The definitions of one name, the scoped ones (locals, parameters, labels)
// by where their body starts: bodies do not overlap, so the ones in scope
// at a place are those of the last body starting before it.
struct NameDefs {
  std::vector<const Definition*> unscoped;
  std::vector<const Definition*> scoped;

  std::vector<const Definition*> candidates(const Place& where) const {
    std::vector<const Definition*> out = unscoped;
    Definition probe;
    probe.scope = Range{where, where};
    auto end = std::upper_bound(scoped.begin(), scoped.end(), &probe, scope_before);
    for (auto it = end; it != scoped.begin() && contains(*(*(it - 1))->scope, where); --it) out.push_back(*(it - 1));
    std::reverse(out.begin() + static_cast<std::ptrdiff_t>(unscoped.size()), out.end());
    return out;
  }
};

}  // namespace

std::vector<std::pair<const Occurrence*, const Definition*>> resolve_file(const Index& index, std::uint32_t file) {
  // A table of every definition by name: resolving each identifier against
  // all definitions made a 20,000-line document take seconds, and so did
  // 4,000 functions' parameters all named `a` without the order by body.
  std::unordered_map<std::string_view, NameDefs> by_name;
  for (const auto& d : index.defs) (d.scope ? by_name[d.name].scoped : by_name[d.name].unscoped).push_back(&d);
  for (auto& [name, defs] : by_name) std::stable_sort(defs.scoped.begin(), defs.scoped.end(), scope_before);
  std::vector<std::pair<const Occurrence*, const Definition*>> out;
  for (const auto& o : index.occurrences) {
    if (o.at.begin.file != file) continue;
    auto it = by_name.find(o.name);
    out.emplace_back(&o, it == by_name.end() ? nullptr : resolve_among(it->second.candidates(o.at.begin), o.at.begin));
  }
  return out;
}

std::size_t utf8_length(unsigned char lead) {
  if (lead < 0x80) return 1;
  if ((lead >> 5) == 0x6) return 2;
  if ((lead >> 4) == 0xe) return 3;
  if ((lead >> 3) == 0x1e) return 4;
  return 1;  // a stray continuation byte counts as one
}

std::uint32_t utf16_column(const Index& index, const Place& at) {
  const std::uint32_t size = static_cast<std::uint32_t>(index.sm.line(at.file, at.line).size());
  const std::uint32_t bytes = at.column > 0 ? at.column - 1 : 0;
  const std::uint32_t within = std::min(bytes, size);
  const std::uint32_t past_end = bytes - within;
  if (at.file >= index.wide_chars.size()) return bytes;
  const auto& wide = index.wide_chars[at.file];
  // The last wide character of the line that starts before the column.
  auto after = std::partition_point(wide.begin(), wide.end(), [&](const WideChar& w) {
    return w.line < at.line || (w.line == at.line && w.start < within);
  });
  if (after == wide.begin() || (after - 1)->line != at.line) return bytes;
  const WideChar& w = *(after - 1);
  return (within >= w.end ? w.units + (within - w.end) : w.units) + past_end;
}

bool in_stdlib(const Index& index, std::uint32_t file) { return file < index.is_stdlib.size() && index.is_stdlib[file]; }

bool on_command_line(const Index& index, std::uint32_t file) { return index.command_line == file; }

std::vector<Range> references(const Index& index, const Definition& def, bool with_declaration) {
  std::vector<Range> out;
  std::set<std::tuple<std::string, std::uint32_t, std::uint32_t>> seen;  // a file read twice counts once
  // The definitions of the name are found once, not again for each use:
  // a name used 12,000 times among 8,000 definitions took 0.3 s.
  const std::vector<const Definition*> candidates = named(index, def.name);
  for (const auto& o : index.occurrences) {
    if (o.name != def.name) continue;
    if (resolve_among(candidates, o.at.begin) != &def) continue;
    if (!with_declaration && o.at.begin.file == def.at.begin.file && o.at.begin.line == def.at.begin.line &&
        o.at.begin.column == def.at.begin.column)
      continue;
    if (!seen.insert({index.sm.path(o.at.begin.file), o.at.begin.line, o.at.begin.column}).second) continue;
    out.push_back(o.at);
  }
  return out;
}

std::vector<const Definition*> visible_at(const Index& index, const Place& where) {
  std::vector<const Definition*> out;
  std::set<std::string> names;
  auto take = [&](const Definition& d) {
    if (starts_with(d.name, "__")) return;
    if (names.insert(d.name).second) out.push_back(&d);
  };
  for (const auto& d : index.defs)
    if (d.scope && contains(*d.scope, where)) take(*resolve(index, d.name, where));
  for (const auto& d : index.defs)
    if (!d.scope) take(d);
  return out;
}

namespace {

// Walks back from the last token before the cursor; a ';' or a brace ends
// the search, as no argument list spans a statement.
std::optional<CallSite> open_call(const std::vector<frontend::Token>& tokens, std::size_t end) {
  std::size_t depth = 0, commas = 0;
  for (std::size_t i = end; i-- > 0;) {
    const auto& t = tokens[i];
    if (t.is(";") || t.is("{") || t.is("}")) return std::nullopt;
    if (t.is(")")) {
      ++depth;
    } else if (t.is("(") && depth > 0) {
      --depth;
    } else if (t.is("(")) {
      if (i > 0 && tokens[i - 1].kind == frontend::TokenKind::Identifier && !frontend::is_keyword(tokens[i - 1].text))
        return CallSite{std::string(tokens[i - 1].text), place_of(tokens[i - 1].span.begin), commas};
      commas = 0;  // a parenthesised expression inside an argument: look further out
    } else if (t.is(",") && depth == 0) {
      ++commas;
    }
  }
  return std::nullopt;
}

// The offset of the '(' that opens the parameter list in the signature.
// A function-like macro has it right after the name ("#define X (1)" has
// none), and the name is looked for after "define" ("#define def(x)").
std::optional<std::size_t> list_opening(const Definition& def) {
  std::size_t from = def.kind == DefKind::Macro ? def.signature.find("define") : 0;
  if (from == std::string::npos) return std::nullopt;
  if (def.kind == DefKind::Macro) from += 6;
  auto at = def.signature.find(def.name + "(", from);
  if (at == std::string::npos) return std::nullopt;
  if (def.kind == DefKind::Macro && !trim(std::string_view(def.signature).substr(from, at - from)).empty()) return std::nullopt;
  return at + def.name.size();
}

}  // namespace

std::optional<CallSite> call_at(const Index& index, const Place& where) {
  if (where.file != index.main_file) return std::nullopt;
  Diagnostics ignored;
  // The lexer skips comments and reads strings and characters whole, so
  // commas in them are no separators.
  std::vector<frontend::Token> tokens = frontend::lex(index.sm.text(where.file), where.file, ignored);
  // A position past the end of the document is nowhere, not in a call
  // left open on its last line.
  if (before(place_of(tokens.back().span.begin), where)) return std::nullopt;
  auto first_after = std::partition_point(tokens.begin(), tokens.end(), [&](const frontend::Token& t) {
    return t.kind != frontend::TokenKind::End && before(place_of(t.span.begin), where);
  });
  return open_call(tokens, static_cast<std::size_t>(first_after - tokens.begin()));
}

bool before(const Place& a, const Place& b) { return a.line < b.line || (a.line == b.line && a.column < b.column); }

std::vector<CallArguments> calls_in(const Index& index, std::uint32_t file) {
  Diagnostics ignored;
  std::vector<frontend::Token> tokens = frontend::lex(index.sm.text(file), file, ignored);
  std::vector<CallArguments> calls;
  // The calls still open, by their index in `calls`; a '(' that only
  // groups is kNotACall, so its ')' closes nothing of theirs.
  constexpr std::size_t kNotACall = static_cast<std::size_t>(-1);
  std::vector<std::size_t> open;
  std::vector<std::size_t> argument_of_open;  // the argument each open '(' is in
  bool argument_starts = false;
  for (std::size_t i = 0; i < tokens.size() && tokens[i].kind != frontend::TokenKind::End; ++i) {
    const frontend::Token& t = tokens[i];
    // A directive's line ends what it opened: `#define F(x) G(x` leaves
    // nothing open into the program.
    if (t.line_start && t.is("#")) open.clear(), argument_of_open.clear(), argument_starts = false;
    bool ends_statement = t.is(";") || t.is("{") || t.is("}");
    if (argument_starts && !t.is(")") && !t.is(",") && !ends_statement) {
      CallArgument a{argument_of_open.back(), place_of(t.span.begin), {}};
      bool alone = i + 1 < tokens.size() && (tokens[i + 1].is(",") || tokens[i + 1].is(")"));
      if (t.kind == frontend::TokenKind::Identifier && alone) a.only_name = std::string(t.text);
      calls[open.back()].arguments.push_back(std::move(a));
    }
    argument_starts = false;
    if (t.is("(")) {
      bool call = i > 0 && tokens[i - 1].kind == frontend::TokenKind::Identifier && !frontend::is_keyword(tokens[i - 1].text);
      if (call) calls.push_back({std::string(tokens[i - 1].text), place_of(tokens[i - 1].span.begin), {}});
      open.push_back(call ? calls.size() - 1 : kNotACall);
      argument_of_open.push_back(0);
      argument_starts = call;
    } else if (t.is(")") && !open.empty()) {
      open.pop_back();
      argument_of_open.pop_back();
    } else if (t.is(",") && !open.empty() && open.back() != kNotACall) {
      ++argument_of_open.back();
      argument_starts = true;
    } else if (ends_statement) {
      open.clear();  // a statement's end closes what a typo left open
      argument_of_open.clear();
    }
  }
  return calls;
}

std::optional<Place> body_opening(const Index& index, const Definition& def) {
  Diagnostics ignored;
  for (const frontend::Token& t : frontend::lex(index.sm.text(def.at.begin.file), def.at.begin.file, ignored))
    if (t.is("{") && before(def.at.begin, place_of(t.span.begin))) return place_of(t.span.begin);
  return std::nullopt;
}

std::optional<ParameterList> parameter_list(const Definition& def) {
  if (def.kind != DefKind::Function && def.kind != DefKind::Sub && def.kind != DefKind::Macro) return std::nullopt;
  auto open = list_opening(def);
  if (!open) return std::nullopt;
  ParameterList list;
  const std::string_view sig = def.signature;
  std::size_t start = *open + 1, depth = 0;
  for (std::size_t i = start; i < sig.size(); ++i) {
    if (sig[i] == '(') ++depth;
    if (depth > 0) {
      if (sig[i] == ')') --depth;
      continue;
    }
    if (sig[i] != ',' && sig[i] != ')') continue;
    auto first = sig.find_first_not_of(" \t", start);
    if (first < i) list.params.emplace_back(first, sig.find_last_not_of(" \t", i - 1) + 1);
    start = i + 1;
    if (sig[i] == ')') {
      list.close = i;
      return list;
    }
  }
  return std::nullopt;  // unbalanced: a #define cut short
}

bool is_identifier(std::string_view s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

bool is_plain_name(std::string_view name) { return is_identifier(name) && !frontend::is_keyword(name); }

const Definition* rename_clash(const Index& index, const std::vector<Range>& uses, const std::string& new_name) {
  const std::vector<const Definition*> candidates = named(index, new_name);
  for (const Range& r : uses)
    if (const Definition* other = resolve_among(candidates, r.begin)) return other;
  return nullptr;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::vector<std::string> similar_names(const Index& index, const std::string& name, const Place& where,
                                       std::size_t limit) {
  auto lower = [](std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  // Each distance costs the product of the lengths (and edit_distance holds
  // the whole table): a long name is no typing slip, so it gets no fixes,
  // as the compiler gives it no "did you mean".
  if (name.size() > frontend::kMaxSpelledName) return {};
  const std::string key = lower(name);
  const std::size_t allowed = std::max<std::size_t>(1, name.size() / 3);
  // Ranked by the distance ignoring case (a slip of the shift key costs
  // less than a wrong letter), then by the exact distance.
  std::vector<std::tuple<std::size_t, std::size_t, std::string>> scored;
  for (const Definition* d : visible_at(index, where)) {
    if (d->name == name || d->kind == DefKind::Label) continue;
    // At least one edit per letter of difference in length.
    if ((d->name.size() > name.size() ? d->name.size() - name.size() : name.size() - d->name.size()) > allowed) continue;
    std::size_t dist = edit_distance(key, lower(d->name));
    if (dist > allowed) continue;
    scored.emplace_back(dist, edit_distance(name, d->name), d->name);
  }
  std::sort(scored.begin(), scored.end());
  std::vector<std::string> out;
  for (const auto& [folded, exact, n] : scored) {
    if (out.size() == limit) break;
    out.push_back(n);
  }
  return out;
}

bool contains(const Range& r, const Place& p) {
  return p.file == r.begin.file && !before(p, r.begin) && before(p, r.end);
}

}  // namespace rcxc::lsp
