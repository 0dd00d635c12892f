// A limit on how deeply the syntax tree nests. Semantic analysis, lowering
// and the IR passes walk the tree recursively, so the depth the source
// chooses (70,000 nested blocks, 100,000 prefix operators, a 200,000-term
// sum, chained ifs or assignments) would otherwise decide how deep the
// compiler's stack goes.
#pragma once

#include <cstddef>
#include <string>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"

namespace rcxc::frontend {

// Statements and expressions inside one another, counted along any path
// from a task, sub, function body or global initialiser down; also the
// deepest brackets may nest. 1000 nested loops around a 1000-deep
// expression (tests/frontend/stress_test.cpp) need about 3000; a level of
// prefix operators costs between 250 bytes and 1 KB of stack in a release
// build (measured with ulimit -s); under ASan a 3990-term sum overflowed
// 8 MB in lowering while 3190 levels of every shape tried passed.
inline constexpr int kMaxNesting = 3200;

// Reports an error at the first node of each body or initialiser that is
// nested more than kMaxNesting deep, and replaces that body with an empty
// block (an initialiser with 0), taken apart without recursion so that even
// destroying the tree cannot overflow the stack. Returns true when nothing
// was too deep.
bool limit_nesting(ast::Program& program, Diagnostics& diags);

// The error for a tree or parse nested past kMaxNesting.
std::string too_deep_message();

// The parser's stack holds at most this many entries per level of nesting
// (a `for` head and its block take ten), so a deeper stack means the input
// nests past kMaxNesting: the parse stops there, before the stack grows
// with the input (100,000 `x =` or prefix operators in a row).
inline constexpr std::size_t kMaxParserStack = 12 * static_cast<std::size_t>(kMaxNesting);

}  // namespace rcxc::frontend
