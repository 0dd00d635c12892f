// The preprocessor: #include, #define (object- and function-like, # and ##),
// conditionals, #error, #pragma, over the lexer's tokens. Macro uses are
// recorded in the SourceManager so diagnostics can name them.
#pragma once

#include <cstdint>
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
};

// Preprocesses file `file` (already added to `sm`, with `dir` as the folder
// its quoted includes are searched in first; "" for none). Unless
// options.no_stdlib, the stdlib's rcx.nqh is read before it.
Preprocessed preprocess(std::uint32_t file, const std::string& dir, const Options& options, SourceManager& sm,
                        Diagnostics& diags);

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
