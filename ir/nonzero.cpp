// `d = (v != 0)` by the sign and absolute value instructions (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool sets_constant(const Instr& in, VarId d, int value) {
  return !in.raw && in.op == rcx::Op::SetVariable && in.args.size() == 2 && in.args[0].is_var(d) &&
         in.args[1] == Operand::imm(value);
}

}  // namespace

void compute_nonzero_by_sign(Function& f, const std::vector<Var>& vars, bool other_tasks) {
  std::vector<int> preds = predecessor_counts(f);
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (std::size_t p = 0; p < f.blocks.size(); ++p) {
    Block& test = f.blocks[p];
    const auto* br = std::get_if<Branch>(&test.term);
    if (!br || loop_blocks[p] || test.instrs.empty() || (br->cmp != Cmp::EQ && br->cmp != Cmp::NE)) continue;
    // v == 0 or v != 0, either way round.
    const Operand* v = br->a == Operand::imm(0) ? &br->b : br->b == Operand::imm(0) ? &br->a : nullptr;
    if (!v || v->is_imm() || reads_random(*v) || !accepts(rcx::Op::AbsoluteValue, 1, *v)) continue;
    BlockId nonzero = br->cmp == Cmp::NE ? br->then : br->otherwise;
    BlockId zero = br->cmp == Cmp::NE ? br->otherwise : br->then;
    // The side where v != 0 only sets d to 1 and goes on to where the
    // other side goes: d = 0 before the test, 1 there.
    const Block& one = f.blocks[static_cast<std::size_t>(nonzero)];
    const auto* j = std::get_if<Jump>(&one.term);
    if (nonzero == static_cast<BlockId>(p) || zero == nonzero || !j || j->target != zero ||
        preds[static_cast<std::size_t>(nonzero)] != 1 || loop_blocks[static_cast<std::size_t>(nonzero)] ||
        one.instrs.size() != 1 || !one.instrs[0].args[0].is_var())
      continue;
    VarId d = one.instrs[0].args[0].value;
    if (!sets_constant(one.instrs[0], d, 1) || !sets_constant(test.instrs.back(), d, 0) || v->is_var(d)) continue;
    // A task waiting for d > 1 would see |v|; nqc's code shows 0 and 1.
    if (other_tasks && shared_between_tasks(vars.at(static_cast<std::size_t>(d)))) continue;
    // d = |v| then its sign: 0 or 1 (|-32768| is 32767 on the firmware).
    Instr abs = test.instrs.back(), sign = test.instrs.back();
    abs.op = rcx::Op::AbsoluteValue;
    abs.args = {Operand::var(d), *v};
    sign.op = rcx::Op::SignVariable;
    sign.args = {Operand::var(d), Operand::var(d)};
    test.instrs.back() = abs;
    test.instrs.push_back(sign);
    test.term = Jump{zero};
    --preds[static_cast<std::size_t>(nonzero)];
  }
}

}  // namespace rcxc::ir
