// Lowering: the checked AST of a program to IR.
//
// Tasks and subroutines become IR functions (tasks first, in source order,
// then subroutines); inline functions are expanded at every call with the
// semantics of their four parameter kinds; expressions map onto RCX
// source/argument operands where the opcode accepts them and go through
// compiler temporaries otherwise. Operators the firmware lacks (% ^ << >>
// ! comparisons, ?:, && and || as values) are built from the ones it has.
#pragma once

#include <optional>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"
#include "ir/ir.h"

namespace rcxc::ir {

// nullopt after reporting errors to `diags` (for instance a recursive
// inline function or a reference parameter given a non-variable).
std::optional<Program> lower(const ast::Program& program, Diagnostics& diags);

}  // namespace rcxc::ir
