// Operand ranges the firmware reference states (sound 0..5, timer 0..3, ...)
// and the check that constant arguments of inline functions stay in them
// once they reach an instruction, e.g. PlaySound(7).
#pragma once

#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"

namespace rcxc::frontend {

// The range the seed gives for operand `operand` of the instruction
// `mnemonic` (for a source operand: its value when it is a constant).
std::optional<std::pair<int, int>> operand_range(std::string_view mnemonic, std::string_view operand);

// Warns at `call` when a constant argument of the call of `f` (after sema
// resolved `program`) ends up as an instruction operand outside its range,
// following the argument through nested inline calls.
void check_call_ranges(const ast::Program& program, const ast::Function& f, const std::vector<ast::Expr>& args,
                       SourceSpan call, Diagnostics& diags);

}  // namespace rcxc::frontend
