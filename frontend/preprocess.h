// The preprocessor: #include, #define (object- and function-like, # and ##),
// conditionals, #error, #pragma, over the lexer's tokens. Macro uses are
// recorded in the SourceManager so diagnostics can name them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "frontend/ast.h"
#include "frontend/frontend.h"
#include "frontend/token.h"

namespace rcxc::frontend {

struct Preprocessed {
  std::vector<Token> tokens;  // ends with one End token
  ast::Pragmas pragmas;
  // False when preprocessing stopped early (a macro expansion without
  // bound): the tokens end in the middle of the program, so parsing them
  // would only add errors about a cut the user did not make.
  bool complete = true;
  std::vector<std::string> macro_names;  // defined at the end, for "did you mean"
  std::vector<std::string> function_macro_names;  // those of them that take arguments
  // The macros an #undef removed and nothing defined again, each with the
  // name in the #undef: a later use is told where it went.
  std::vector<std::pair<std::string, SourceSpan>> undefined_macros;
};

// Preprocesses file `file` (already added to `sm`, with `dir` as the folder
// its quoted includes are searched in first; "" for none). Unless
// options.no_stdlib, the stdlib's rcx.nqh is read before it.
Preprocessed preprocess(std::uint32_t file, const std::string& dir, const Options& options, SourceManager& sm,
                        Diagnostics& diags);

// The preprocessor's state right after reading the stdlib (its macros, its
// tokens, the files and macro uses it added to the SourceManager), so that
// many compilations with the same -D/-U need not read rcx.nqh each time.
struct StdlibState;
// nullptr with -n, or when reading the stdlib reported anything.
std::shared_ptr<const StdlibState> preprocess_stdlib(const Options& options);
// Whether `stdlib` was made with these options and `sm` holds just the
// file to preprocess (the stdlib's files then get the ids they had).
bool fits(const StdlibState& stdlib, const Options& options, const SourceManager& sm);
// The stdlib's own tokens (without End).
const std::vector<Token>& stdlib_tokens(const StdlibState& stdlib);
// As preprocess(), starting from `stdlib` (which must fit): the tokens are
// the file's only, the macros and the SourceManager as if rcx.nqh was read.
Preprocessed preprocess_after_stdlib(const StdlibState& stdlib, std::uint32_t file, const std::string& dir,
                                     const Options& options, SourceManager& sm, Diagnostics& diags);

// Renders tokens back to text for `rcxc compile -E`: one source line per
// output line, with `# LINE "FILE"` markers when the file or line jumps.
std::string tokens_to_text(const std::vector<Token>& tokens, const SourceManager& sm);

// The location a user would name for `loc`: for text that came out of macro
// bodies, the place in the file where the outermost macro was used.
SourceLoc presumed_loc(const SourceLoc& loc, const SourceManager& sm);

// Why `text` read from `path` cannot be NQC source (an RCX image, other
// binary data), or "" when it may be. Checked before lexing, so a wrong
// file gives one clear error instead of one per stray byte.
std::string not_source_reason(const std::string& path, std::string_view text);

}  // namespace rcxc::frontend
