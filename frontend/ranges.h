// Operand ranges the firmware reference states (sound 0..5, timer 0..3, ...)
// and the check that constant arguments of inline functions stay in them
// once they reach an instruction, e.g. PlaySound(7).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"

namespace rcxc::frontend {

// The range the seed gives for operand `operand` of the instruction
// `mnemonic` (for a source operand: its value when it is a constant), and
// what the value means where the operand's name does not say (`pwr`'s
// "source" is the power level).
struct OperandRange {
  int lo = 0, hi = 0;
  std::string_view meaning;
  std::string_view effect;  // what the brick does with a value outside, when the seed says
};
std::optional<OperandRange> operand_range(std::string_view mnemonic, std::string_view operand);
// "operand 'source' (the power level) of 'pwr'", for messages.
std::string describe_operand(std::string_view mnemonic, std::string_view operand, const OperandRange& range);
// ", outside the RCX's range 0..7; the RCX ignores the command", for messages.
std::string outside_range(const OperandRange& range);

// What check_call_ranges learnt about the functions of one program: for
// each (by index), whether its body or an inline function it calls has an
// instruction operand with a range that is not written as a constant. Only
// such a function can warn; most have none, and then a call is not
// followed through every body it inlines. Owned by whoever checks the calls.
struct RangeMemo {
  std::vector<std::int8_t> may_warn;  // -1 not known yet, 0 no, 1 yes
};

// Warns at `call` when a constant argument of the call of `f` (after sema
// resolved `program`) ends up as an instruction operand outside its range,
// following the argument through nested inline calls.
void check_call_ranges(const ast::Program& program, const ast::Function& f, const std::vector<ast::Expr>& args,
                       SourceSpan call, Diagnostics& diags, RangeMemo& memo);

}  // namespace rcxc::frontend
