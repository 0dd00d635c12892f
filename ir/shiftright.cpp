// Logical right shifts without a test of the sign (see passes.h).
//
// The firmware divides (truncating) but has no shift, so `d >>= n` is
// lowered as a test of d's sign: below zero `d &= 32767; d /= 2^n;
// d |= 2^(15-n)`, else `d /= 2^n`. Clearing the n low bits first makes d
// a multiple of 2^n, whose quotient is exact whatever the rounding (so a
// negative d gives its floor, the arithmetic shift); the mask then keeps
// the 16 - n bits a logical shift leaves: `d &= -2^n; d /= 2^n; d &=
// 2^(16-n) - 1`. For n = 15 only the sign bit is left: `d &= -32768;
// d /= -32768` is 1 for a negative d and 0 otherwise, which the lowering
// sets by a test (`d = 1` on one side, `d = 0` on the other).
#include <initializer_list>
#include <optional>
#include <utility>
#include <vector>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool is_arith(const Instr& in, rcx::Op op, VarId d, int value) {
  return !in.raw && in.op == op && in.args.size() == 2 && in.args[0].is_var(d) && in.args[1] == Operand::imm(value);
}

// The sides of a test of d's sign, when the branch is one: `d < 0`,
// `d >= 0`, `0 > d` or `0 <= d`.
struct SignTest {
  VarId d = 0;
  BlockId negative = 0, other = 0;
};

std::optional<SignTest> sign_test(const Branch& br) {
  Cmp cmp = br.cmp;
  const Operand *v = &br.a, *k = &br.b;
  if (br.a.is_imm()) {
    cmp = swap(cmp);
    std::swap(v, k);
  }
  if (!v->is_var() || !(*k == Operand::imm(0))) return std::nullopt;
  if (cmp == Cmp::LT) return SignTest{v->value, br.then, br.otherwise};
  if (cmp == Cmp::GE) return SignTest{v->value, br.otherwise, br.then};
  return std::nullopt;
}

// A block no other edge enters, holding exactly `ops` and jumping on.
std::optional<BlockId> only_these(const Function& f, const std::vector<int>& preds, BlockId b,
                                  std::initializer_list<std::pair<rcx::Op, int>> ops, VarId d) {
  const Block& block = f.blocks[static_cast<std::size_t>(b)];
  const auto* j = std::get_if<Jump>(&block.term);
  if (!j || preds[static_cast<std::size_t>(b)] != 1 || block.instrs.size() != ops.size()) return std::nullopt;
  std::size_t i = 0;
  for (const auto& [op, value] : ops)
    if (!is_arith(block.instrs[i++], op, d, value)) return std::nullopt;
  return j->target;
}

}  // namespace

void shift_right_without_branches(Function& f, const std::vector<Var>& vars, bool other_tasks, bool constant_shifts) {
  std::vector<int> preds = predecessor_counts(f);
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (std::size_t p = 0; p < f.blocks.size(); ++p) {
    const auto* br = std::get_if<Branch>(&f.blocks[p].term);
    if (!br || loop_blocks[p]) continue;
    auto test = sign_test(*br);
    if (!test || test->negative == test->other || test->negative == static_cast<BlockId>(p) ||
        test->other == static_cast<BlockId>(p))
      continue;
    VarId d = test->d;
    // A task waiting for d == -32768 would see it: the tested form shows
    // d only as it was and as it ends.
    if (other_tasks && shared_between_tasks(vars.at(static_cast<std::size_t>(d)))) continue;
    std::vector<Instr> straight;
    std::optional<BlockId> join, join2;
    const Instr& model = f.blocks[static_cast<std::size_t>(test->other)].instrs.empty()
                             ? Instr{}
                             : f.blocks[static_cast<std::size_t>(test->other)].instrs.front();
    auto make = [&](rcx::Op op, int value) {
      Instr in = model;
      in.op = op;
      in.args = {Operand::var(d), Operand::imm(value)};
      straight.push_back(in);
    };
    // n = 15: `d = 1` when negative, `d = 0` otherwise.
    join = only_these(f, preds, test->negative, {{rcx::Op::SetVariable, 1}}, d);
    join2 = only_these(f, preds, test->other, {{rcx::Op::SetVariable, 0}}, d);
    if (join && join2 && *join == *join2) {
      make(rcx::Op::AndVariable, -32768);
      make(rcx::Op::DivideVariable, -32768);
    } else if (constant_shifts) {
      for (int n = 1; n <= 14 && straight.empty(); ++n) {
        join = only_these(f, preds, test->negative,
                          {{rcx::Op::AndVariable, 0x7fff}, {rcx::Op::DivideVariable, 1 << n},
                           {rcx::Op::OrVariable, 1 << (15 - n)}},
                          d);
        join2 = only_these(f, preds, test->other, {{rcx::Op::DivideVariable, 1 << n}}, d);
        if (!join || !join2 || *join != *join2) continue;
        make(rcx::Op::AndVariable, wrap16(-(1L << n)));
        make(rcx::Op::DivideVariable, 1 << n);
        make(rcx::Op::AndVariable, (1 << (16 - n)) - 1);
      }
    }
    if (straight.empty()) continue;
    Block& block = f.blocks[p];
    for (BlockId side : {test->negative, test->other}) {
      f.blocks[static_cast<std::size_t>(side)].instrs.clear();
      --preds[static_cast<std::size_t>(side)];
    }
    block.instrs.insert(block.instrs.end(), straight.begin(), straight.end());
    block.term = Jump{*join};
  }
}

}  // namespace rcxc::ir
