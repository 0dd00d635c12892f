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

}  // namespace rcxc::frontend
