// Constant arithmetic at a join moved into the constants that reach it
// (see passes.h).
#include <optional>

#include "ir/liveness.h"
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

// The constant block p sets v to on its way into join j, when that
// constant reaches only the join: every other way out of p sets v again
// before reading it.
Instr* constant_into(Function& f, const std::vector<bool>& loop_blocks, BlockId p, BlockId j, VarId v) {
  Block& pred = f.blocks[static_cast<std::size_t>(p)];
  if (p == j || loop_blocks[static_cast<std::size_t>(p)]) return nullptr;
  for (BlockId s : successors(pred.term))
    if (s != j && !overwrites_first(f.blocks[static_cast<std::size_t>(s)], v)) return nullptr;
  return constant_set_at_end(pred, v);
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
        Instr* set = constant_into(f, loop_blocks, p, static_cast<BlockId>(j), v);
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

namespace {

// Whether v is read after instruction `k` of block b before being set.
bool read_after(const Block& b, std::size_t k, VarId v, const Liveness& L, std::size_t index) {
  for (std::size_t i = k + 1; i < b.instrs.size(); ++i) {
    const Instr& in = b.instrs[i];
    if (!touches(in, v)) continue;
    return !(!in.raw && in.op == rcx::Op::SetVariable && in.args[0].is_var(v) && !in.args[1].is_var(v));
  }
  return reads(b.term, v) || L.live_out[index].has(v);
}

}  // namespace

void apply_constants_in_predecessors(Program& p) {
  std::optional<CallEffects> calls;
  for (auto& f : p.functions) {
    const PredecessorLists preds(f, false);  // applying constants leaves the edges
    const std::vector<bool> loop_blocks = repeat_blocks(f);
    std::optional<Liveness> L;
    for (std::size_t j = 1; j < f.blocks.size(); ++j) {
      Block& join = f.blocks[j];
      if (loop_blocks[j] || preds[j].empty() || join.instrs.empty()) continue;
      // `V op= t` first, t a temporary or local every way in has just set
      // to a constant (a comparison's 0 or 1).
      const Instr& first = join.instrs.front();
      if (first.raw || first.args.size() != 2 || !first.args[0].is_var() || !first.args[1].is_var() ||
          first.args[0] == first.args[1] || first.op == rcx::Op::SetVariable || first.op == rcx::Op::AbsoluteValue ||
          first.op == rcx::Op::SignVariable || !arithmetic(first.op, 0, 0))
        continue;
      VarId t = first.args[1].value;
      if (p.vars[static_cast<std::size_t>(t)].kind == VarKind::Global) continue;
      std::vector<std::pair<BlockId, int>> constants;
      for (BlockId b : preds[j]) {
        const Block& pred = f.blocks[static_cast<std::size_t>(b)];
        Instr* set = constant_into(f, loop_blocks, b, static_cast<BlockId>(j), t);
        // A constant that changes V is applied at the end of its block,
        // which must then go nowhere else.
        if (set && !leaves_unchanged(first.op, set->args[1].value) && !std::holds_alternative<Jump>(pred.term))
          set = nullptr;
        if (!set) {
          constants.clear();
          break;
        }
        constants.emplace_back(b, set->args[1].value);
      }
      if (constants.empty()) continue;
      if (!L) {
        if (!calls) calls = call_effects(p);
        L = compute_liveness(p, f, *calls);
      }
      if (read_after(join, 0, t, *L, j)) continue;
      Instr applied = first;
      for (auto [b, k] : constants) {
        if (leaves_unchanged(first.op, k)) continue;
        applied.args[1] = Operand::imm(k);
        f.blocks[static_cast<std::size_t>(b)].instrs.push_back(applied);
      }
      join.instrs.erase(join.instrs.begin());
    }
  }
}

}  // namespace rcxc::ir
