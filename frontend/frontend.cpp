#include "frontend/frontend.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <fstream>
#include <sstream>
#include <unordered_set>

#include "frontend/parse.h"
#include "frontend/preprocess.h"
#include "frontend/sema.h"
#include "frontend/stdlib_cache.h"
#include "rcx/file_read.h"

namespace rcxc::frontend {

struct StdlibCache {
  std::shared_ptr<const StdlibState> state;
  ast::Program program;  // the stdlib's declarations, parsed, not checked
};

namespace {

std::optional<std::uint32_t> load(const std::string& path, SourceManager& sm, Diagnostics& diags) {
  const bool piped = path == kStandardInput;
  auto [name, file] = read_source(path);
  if (const auto* problem = std::get_if<rcx::FileProblem>(&file)) {
    switch (*problem) {
      case rcx::FileProblem::Directory: diags.error({}, "'" + name + "' is a directory, not a source file").file = name; break;
      case rcx::FileProblem::TooLarge: diags.error({}, rcx::too_large_message(name, rcx::kSourceFile)).file = name; break;
      case rcx::FileProblem::CannotOpen: case rcx::FileProblem::ReadError:
        diags.error({}, piped ? "cannot read the standard input"
                              : "cannot open '" + name + "': " + rcx::cannot_open_reason(path)).file = name;
    }
    return std::nullopt;
  }
  std::string& text = std::get<std::string>(file);
  if (std::string why = not_source_reason(name, text); !why.empty()) {
    diags.error({}, why).file = name;
    return std::nullopt;
  }
  return sm.add(name, std::move(text));
}

std::string folder_of(const std::string& path) {
  std::string dir = std::filesystem::path(path).parent_path().string();
  return dir.empty() ? "." : dir;
}

bool contains(const SourceSpan& outer, const SourceLoc& at) {
  return at.file == outer.begin.file && at.expansion == 0 && outer.begin.expansion == 0 && !before(at, outer.begin) &&
         before(at, outer.end);
}

// After syntax errors, the task, sub and function bodies they are in are
// set aside (emptied; not for errors the parser read past) and the rest of
// the program is still checked, so one
// run reports the semantic errors too. An error outside every body (a
// broken declaration) could make all that follows look wrong: then the
// checks are skipped, as a half-parsed declaration would only repeat it.
void check_around_syntax_errors(ast::Program& program, Diagnostics& diags,
                                const std::vector<std::string>& function_macro_names) {
  std::vector<ast::Stmt*> bodies;
  for (auto& t : program.tasks) bodies.push_back(&t.body);
  for (auto& s : program.subs) bodies.push_back(&s.body);
  for (auto& f : program.functions) bodies.push_back(&f.body);
  std::vector<bool> broken(bodies.size(), false);
  bool whole = true;  // every error one the parser read past
  for (const auto& d : diags.all()) {
    if (d.severity != Severity::Error || d.parsed_past) continue;
    whole = false;
    bool placed = false;
    for (std::size_t b = 0; b < bodies.size() && !placed; ++b)
      if (contains(bodies[b]->span, d.span.begin)) placed = broken[b] = true;
    if (!placed) return;
  }
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (broken[b]) bodies[b]->node = ast::Block{};
  check(program, diags, function_macro_names, whole);
}

// An inline function defined at the standard library's top level: its
// tokens [begin, end) and the names its body uses.
struct LibraryFunction {
  std::string_view name;
  std::size_t begin = 0, end = 0;
  bool reached = false;
};

// Index of the token that closes the bracket at `open` (before `limit`), or
// `limit` when it is not closed there.
std::size_t closing(const std::vector<Token>& tokens, std::size_t open, std::size_t limit) {
  std::string_view opener = tokens[open].text, closer = opener == "(" ? ")" : "}";
  int depth = 0;
  for (std::size_t i = open; i < limit; ++i) {
    if (tokens[i].kind != TokenKind::Punct) continue;
    if (tokens[i].text == opener) ++depth;
    if (tokens[i].text == closer && --depth == 0) return i;
  }
  return limit;
}

// The standard library defines dozens of inline functions and a program
// calls a few; parsing and checking all of them was most of the library's
// cost, paid at every start. These are the preprocessed tokens without the
// library's function definitions that nothing the program says reaches
// (directly or through the library functions it does reach; macros are
// already expanded, so a macro's use counts). nullopt when every one is
// reached or the library's text is not in the expected shape.
std::optional<std::vector<Token>> without_unreached_library_functions(const std::vector<Token>& tokens,
                                                                      const SourceManager& sm,
                                                                      const ast::Pragmas& pragmas) {
  // rcx.nqh is read before the program, so its tokens come first.
  std::size_t library_end = 0;
  while (library_end < tokens.size() && tokens[library_end].kind != TokenKind::End &&
         sm.is_library(presumed_loc(tokens[library_end].span.begin, sm).file))
    ++library_end;
  std::vector<LibraryFunction> functions;
  std::unordered_set<std::string_view> used;
  auto use_names = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (tokens[i].kind == TokenKind::Identifier) used.insert(tokens[i].text);
  };
  int depth = 0;
  for (std::size_t i = 0; i < library_end;) {
    const Token& t = tokens[i];
    std::size_t head = i + (t.is_identifier("inline") ? 1 : 0);
    if (depth == 0 && head + 2 < library_end && tokens[head].is_identifier("void") &&
        tokens[head + 1].kind == TokenKind::Identifier && tokens[head + 2].is("(")) {
      std::size_t params_end = closing(tokens, head + 2, library_end);
      if (params_end + 1 >= library_end || !tokens[params_end + 1].is("{")) return std::nullopt;
      std::size_t body_end = closing(tokens, params_end + 1, library_end);
      if (body_end == library_end) return std::nullopt;
      functions.push_back({tokens[head + 1].text, i, body_end + 1, false});
      i = body_end + 1;
      continue;
    }
    if (t.kind == TokenKind::Punct && (t.text == "(" || t.text == "{" || t.text == "[")) ++depth;
    if (t.kind == TokenKind::Punct && (t.text == ")" || t.text == "}" || t.text == "]")) --depth;
    use_names(i, i + 1);
    ++i;
  }
  use_names(library_end, tokens.size());
  if (pragmas.init) used.insert(*pragmas.init);  // the startup code calls it
  for (bool grew = true; grew;) {
    grew = false;
    for (auto& f : functions)
      if (!f.reached && used.count(f.name)) {
        f.reached = grew = true;
        // The parameters' and body's names, the function's own included.
        use_names(f.begin, f.end);
      }
  }
  if (std::all_of(functions.begin(), functions.end(), [](const LibraryFunction& f) { return f.reached; }))
    return std::nullopt;
  std::vector<Token> kept;
  kept.reserve(tokens.size());
  std::size_t from = 0;
  for (const auto& f : functions) {
    if (f.reached) continue;
    kept.insert(kept.end(), tokens.begin() + static_cast<std::ptrdiff_t>(from),
                tokens.begin() + static_cast<std::ptrdiff_t>(f.begin));
    from = f.end;
  }
  kept.insert(kept.end(), tokens.begin() + static_cast<std::ptrdiff_t>(from), tokens.end());
  return kept;
}

// Parses and checks the program with only the library functions it
// reaches. Kept when that finds no error: with the rest of the library
// unchanged (it has no problems of its own) the program and its warnings
// are the same. After an error the caller checks again with the whole
// library, so messages (did you mean ...) still see every name.
std::optional<ast::Program> parse_reached(const std::vector<Token>& tokens, const ast::Pragmas& pragmas,
                                          const SourceManager& sm, Diagnostics& diags) {
  auto reached = without_unreached_library_functions(tokens, sm, pragmas);
  if (!reached) return std::nullopt;
  Diagnostics trial;
  trial.policy = diags.policy;
  ast::Program program = parse_tokens(std::move(*reached), trial);
  program.pragmas = pragmas;  // sema checks what `#pragma init` names
  if (!trial.has_errors()) check(program, trial);
  if (trial.has_errors()) return std::nullopt;
  for (const auto& d : trial.all()) diags.add(d);
  return program;
}

// `after` appended to `before`: the declarations of both, in order.
ast::Program joined(const ast::Program& before, ast::Program after) {
  ast::Program program = before;
  auto offset = [&](ast::SymbolKind kind) {
    switch (kind) {
      case ast::SymbolKind::Global: return before.globals.size();
      case ast::SymbolKind::Task: return before.tasks.size();
      case ast::SymbolKind::Sub: return before.subs.size();
      default: return before.functions.size();
    }
  };
  for (auto ref : after.order) {
    ref.index += static_cast<std::uint32_t>(offset(ref.kind));
    program.order.push_back(ref);
  }
  std::move(after.globals.begin(), after.globals.end(), std::back_inserter(program.globals));
  std::move(after.tasks.begin(), after.tasks.end(), std::back_inserter(program.tasks));
  std::move(after.subs.begin(), after.subs.end(), std::back_inserter(program.subs));
  std::move(after.functions.begin(), after.functions.end(), std::back_inserter(program.functions));
  return program;
}

std::optional<ast::Program> run(std::uint32_t file, const std::string& dir, const Options& options,
                                SourceManager& sm, Diagnostics& diags, const StdlibCache* cache = nullptr) {
  Preprocessed pp = cache ? preprocess_after_stdlib(*cache->state, file, dir, options, sm, diags)
                          : preprocess(file, dir, options, sm, diags);
  if (!pp.complete) return std::nullopt;
  // The cache (fuzzing, tests) already holds the whole library parsed. A
  // long program skips the trial: the library's parse is then a small part
  // of the work, and the trial's copy of the tokens would double their
  // memory (hostile inputs must stay under 100 MB: SECURITY.md).
  constexpr std::size_t kTrialTokenLimit = 50'000;
  if (!cache && !options.whole_library && !diags.has_errors() && pp.tokens.size() <= kTrialTokenLimit) {
    if (auto program = parse_reached(pp.tokens, pp.pragmas, sm, diags)) {
      program->macro_names = std::move(pp.macro_names);
      program->undefined_macros = std::move(pp.undefined_macros);
      return program;
    }
  }
  ast::Program program = cache ? joined(cache->program, parse_tokens(std::move(pp.tokens), diags))
                               : parse_tokens(std::move(pp.tokens), diags);
  program.pragmas = std::move(pp.pragmas);
  program.macro_names = std::move(pp.macro_names);
  program.undefined_macros = std::move(pp.undefined_macros);
  if (diags.has_errors()) {
    check_around_syntax_errors(program, diags, pp.function_macro_names);
    return std::nullopt;
  }
  check(program, diags, pp.function_macro_names);
  if (diags.has_errors()) return std::nullopt;
  return program;
}

}  // namespace

SourceRead read_source(const std::string& path) {
  if (path == kStandardInput) return {std::string(kStandardInputName), rcx::read_stream(std::cin, rcx::kSourceFile)};
  return {path, rcx::read_file(path, rcx::kSourceFile)};
}

std::optional<ast::Program> parse_program(const std::string& path, const Options& options, SourceManager& sm,
                                          Diagnostics& diags) {
  auto file = load(path, sm, diags);
  if (!file) return std::nullopt;
  return run(*file, folder_of(path), options, sm, diags);
}

std::shared_ptr<const StdlibCache> make_stdlib_cache(const Options& options) {
  auto state = preprocess_stdlib(options);
  if (!state) return nullptr;
  std::vector<Token> tokens = stdlib_tokens(*state);
  Token end;
  end.kind = TokenKind::End;
  tokens.push_back(end);
  Diagnostics diags;
  ast::Program program = parse_tokens(std::move(tokens), diags);
  if (!diags.all().empty()) return nullptr;
  return std::make_shared<const StdlibCache>(StdlibCache{std::move(state), std::move(program)});
}

void Options::define(const std::string& option) {
  auto eq = option.find('=');
  if (eq == std::string::npos)
    defines.emplace_back(option, "1");
  else
    defines.emplace_back(option.substr(0, eq), option.substr(eq + 1));
}

std::optional<ast::Program> parse_source(const std::string& name, std::string text, const Options& options,
                                         SourceManager& sm, Diagnostics& diags) {
  std::uint32_t file = sm.add(name, std::move(text));
  return run(file, folder_of(name), options, sm, diags);
}

std::optional<ast::Program> parse_source(const std::string& name, std::string text, const Options& options,
                                         const StdlibCache* stdlib, SourceManager& sm, Diagnostics& diags) {
  std::uint32_t file = sm.add(name, std::move(text));
  if (stdlib && !fits(*stdlib->state, options, sm)) stdlib = nullptr;
  return run(file, folder_of(name), options, sm, diags, stdlib);
}

std::optional<std::string> preprocess_file(const std::string& path, const Options& options, SourceManager& sm,
                                           Diagnostics& diags) {
  auto file = load(path, sm, diags);
  if (!file) return std::nullopt;
  Preprocessed pp = preprocess(*file, folder_of(path), options, sm, diags);
  if (diags.has_errors()) return std::nullopt;
  return tokens_to_text(pp.tokens, sm);
}

}  // namespace rcxc::frontend
