// The parser (bison, frontend/parser.y): preprocessed tokens in, AST out.
#pragma once

#include <vector>

#include "frontend/ast.h"
#include "frontend/token.h"

namespace rcxc::frontend {

// Parses `tokens` (ending with End) into a Program. Syntax errors are
// reported to `diags`; parsing recovers at ';' and '}' so that one run
// reports many. The result holds what could be parsed, without symbols.
ast::Program parse_tokens(std::vector<Token> tokens, Diagnostics& diags);

}  // namespace rcxc::frontend
