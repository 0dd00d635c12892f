// The parser (bison, frontend/parser.y): preprocessed tokens in, AST out.
#pragma once

#include <string_view>
#include <vector>

#include "frontend/ast.h"
#include "frontend/token.h"

namespace rcxc::frontend {

// Parses `tokens` (ending with End) into a Program. Syntax errors are
// reported to `diags`; parsing recovers at ';' and '}' so that one run
// reports many. The result holds what could be parsed, without symbols.
ast::Program parse_tokens(std::vector<Token> tokens, Diagnostics& diags);

// The words the parser reads as keywords, from the table it looks
// identifiers up in: for tools that offer or check names (the language
// server's completion and rename). Words starting "__" are the standard
// library's, not the user's.
std::vector<std::string_view> keywords();
bool is_keyword(std::string_view word);

// Words nqc reserves that rcxc's grammar does not use (`acquire monitor
// catch __res __event_src`): why nqc has them ("a statement of the RCX 2
// firmware"), or nullptr for any other word. nqc refuses them as names.
const char* reserved_by_nqc(std::string_view word);

// Why `word` cannot be a macro name (nqc's lexer gives its keywords and
// reserved words before the preprocessor sees them: "#define required a
// symbol name"), or nullptr when it can. rcxc's own keywords that nqc has
// as macros or not at all (`until`, `inline`, `__source`, `__source_arg`)
// can.
const char* not_a_macro_name(std::string_view word);

}  // namespace rcxc::frontend
