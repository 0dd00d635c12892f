// Semantic analysis: resolves every name to a symbol, folds constant
// expressions (16-bit wrap), checks calls, loops, switches, labels, asm and
// limits, and warns about unused variables, unreachable code and assignments
// used as conditions. Reports as many independent problems as it can.
#pragma once

#include "frontend/ast.h"
#include "frontend/diagnostics.h"

namespace rcxc::frontend {

inline constexpr int kMaxTasks = 10;  // the firmware's task slots

// `function_macro_names`: the macros that take arguments, defined at the
// end of the program; such a name left in the program lacks its '('.
// `whole`: false after syntax errors, when a task the parser set aside
// (`task main()` after a body left open) may be missing from `program`:
// a missing main is then not reported.
void check(ast::Program& program, Diagnostics& diags, const std::vector<std::string>& function_macro_names = {},
           bool whole = true);

}  // namespace rcxc::frontend
