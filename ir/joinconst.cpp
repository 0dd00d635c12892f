// Constant arithmetic at a join moved into the constants that reach it
// (see passes.h).
#include "ir/passes.h"
#include "ir/predecessors.h"

namespace rcxc::ir {
namespace {

// Whether `in` may read or write v (a temporary or local: no call or
// other task can).
bool touches(const Instr& in, VarId v) {
  if (in.raw) return true;
  VarUse u = uses_of(in);
  for (VarId r : u.reads)
    if (r == v) return true;
  for (VarId w : u.writes)
    if (w == v) return true;
  return !in.args.empty() && in.args[0].is_var(v);  // a read-modify-write
}

bool reads(const Terminator& t, VarId v) {
  for (VarId r : reads_of(t))
    if (r == v) return true;
  return false;
}

// The last instruction of `b` that touches v, when it sets v to a constant
// and nothing after it (the terminator included) reads v.
Instr* constant_set_at_end(Block& b, VarId v) {
  if (reads(b.term, v)) return nullptr;
  for (std::size_t k = b.instrs.size(); k-- > 0;) {
    Instr& in = b.instrs[k];
    if (!touches(in, v)) continue;
    if (in.raw || in.op != rcx::Op::SetVariable || !in.args[0].is_var(v) || !in.args[1].is_imm()) return nullptr;
    return &in;
  }
  return nullptr;
}

// Whether block s overwrites v before anything reads it.
bool overwrites_first(const Block& s, VarId v) {
  for (const auto& in : s.instrs) {
    if (!touches(in, v)) continue;
    return !in.raw && in.op == rcx::Op::SetVariable && in.args[0].is_var(v) && !in.args[1].is_var(v);
  }
  return false;
}

}  // namespace

void push_constant_ops_into_predecessors(Function& f, const std::vector<Var>& vars) {
  const PredecessorLists preds(f, false);  // moving constants leaves the edges
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (std::size_t j = 1; j < f.blocks.size(); ++j) {
    Block& join = f.blocks[j];
    if (loop_blocks[j] || preds[j].empty()) continue;
    // `~(a < b)` ends `t *= -1; t -= 1`: each step in turn.
    while (!join.instrs.empty()) {
      const Instr& first = join.instrs.front();
      if (first.raw || first.args.size() != 2 || !first.args[0].is_var() || !first.args[1].is_imm() ||
          first.op == rcx::Op::SetVariable || !arithmetic(first.op, 0, 0))
        break;
      VarId v = first.args[0].value;
      // Never a global: another task may change it between the set and
      // the join, and the arithmetic must then apply to what it wrote.
      if (vars[static_cast<std::size_t>(v)].kind == VarKind::Global) break;
      std::vector<Instr*> sets;
      bool all = true;
      for (BlockId p : preds[j]) {
        Block& pred = f.blocks[static_cast<std::size_t>(p)];
        Instr* set = p == static_cast<BlockId>(j) || loop_blocks[static_cast<std::size_t>(p)]
                         ? nullptr
                         : constant_set_at_end(pred, v);
        // The constant must reach only this join: every other way out of
        // the block sets v again before reading it.
        for (BlockId s : successors(pred.term))
          if (s != static_cast<BlockId>(j) && !overwrites_first(f.blocks[static_cast<std::size_t>(s)], v))
            set = nullptr;
        if (!set) {
          all = false;
          break;
        }
        sets.push_back(set);
      }
      if (!all) break;
      for (Instr* set : sets) set->args[1] = Operand::imm(*arithmetic(first.op, set->args[1].value, first.args[1].value));
      join.instrs.erase(join.instrs.begin());
    }
  }
}

}  // namespace rcxc::ir
