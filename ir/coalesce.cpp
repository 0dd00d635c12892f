// Computing into the assigned variable instead of into a temporary that is
// then copied (see passes.h).
#include <vector>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

using rcx::Op;

bool is_op(const Instr& in, Op op) { return !in.raw && in.op == op && in.args.size() == 2 && in.args[0].is_var(); }

bool commutes(Op op) {
  return op == Op::AddToVariable || op == Op::MultiplyVariable || op == Op::AndVariable || op == Op::OrVariable;
}

bool arithmetic_op(Op op) {
  return commutes(op) || op == Op::SubtractFromVariable || op == Op::DivideVariable || op == Op::SetVariable;
}

bool reads_var(const Instr& in, VarId v) {
  for (VarId r : uses_of(in).reads)
    if (r == v) return true;
  return false;
}

// Whether `t` (a temporary or local) holds nothing any later code reads
// after instruction k of `block`: `live` is the block's live-out.
bool dead_after(const Program& p, const Block& block, std::size_t k, VarId t, const VarSet& live) {
  for (std::size_t j = k + 1; j < block.instrs.size(); ++j) {
    const Instr& in = block.instrs[j];
    if (in.raw) return false;
    VarUse u = uses_of(in);
    for (VarId r : u.reads)
      if (r == t) return false;
    if (callee_of(in) >= 0) return false;  // what a subroutine keeps is not followed here
    for (VarId w : u.writes)
      if (w == t) return true;
  }
  for (VarId r : reads_of(block.term))
    if (r == t) return false;
  (void)p;
  return !live.has(t);
}

// One scan of a function; returns whether anything changed.
bool coalesce_in(const Program& p, Function& f, const CallEffects& calls) {
  Liveness L = compute_liveness(p, f, calls);
  bool changed = false;
  auto private_var = [&](const Operand& o) {
    if (!o.is_var()) return false;
    const Var& v = p.vars[static_cast<std::size_t>(o.value)];
    return v.kind != VarKind::Global && !v.slot;
  };
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    Block& block = f.blocks[b];
    auto& code = block.instrs;
    const VarSet& live = L.live_out[b];
    for (std::size_t i = 0; i < code.size(); ++i) {
      auto at = [&](std::size_t k) -> const Instr* { return k < code.size() ? &code[k] : nullptr; };
      const Instr* a = at(i);
      const Instr* n1 = at(i + 1);
      const Instr* n2 = at(i + 2);
      if (!is_op(*a, a->op) || !private_var(a->args[0])) continue;
      VarId t = a->args[0].value;
      auto copies_t_into = [&](const Instr* in) -> std::optional<Operand> {
        if (!in || !is_op(*in, Op::SetVariable) || !in->args[1].is_var(t) || in->args[0].is_var(t)) return std::nullopt;
        return in->args[0];
      };
      auto erase = [&](std::size_t from, std::size_t count) {
        code.erase(code.begin() + static_cast<std::ptrdiff_t>(from),
                   code.begin() + static_cast<std::ptrdiff_t>(from + count));
      };

      // `t = X; t -= V; V = t` -> `V -= X; V *= -1`.
      if (a->op == Op::SetVariable && n1 && is_op(*n1, Op::SubtractFromVariable) && n1->args[0].is_var(t) &&
          n1->args[1].is_var()) {
        Operand x = a->args[1], v = n1->args[1];
        auto into = copies_t_into(n2);
        if (into && *into == v && !x.is_var(t) && !(x == v) && !reads_random(x) &&
            accepts(Op::SubtractFromVariable, 1, x) && dead_after(p, block, i + 2, t, live)) {
          Instr sub = *n1, neg = *n1;
          sub.args = {v, x};
          neg.op = Op::MultiplyVariable;
          neg.args = {v, Operand::imm(-1)};
          code[i] = sub;
          code[i + 1] = neg;
          erase(i + 2, 1);
          changed = true;
          continue;
        }
      }
      // `t -= X; t *= -1; V = t` (t = X - t) -> `V -= t` when X is V,
      // else `V = X; V -= t`.
      if (a->op == Op::SubtractFromVariable && n1 && is_op(*n1, Op::MultiplyVariable) && n1->args[0].is_var(t) &&
          n1->args[1] == Operand::imm(-1)) {
        Operand x = a->args[1];
        auto into = copies_t_into(n2);
        if (into && !x.is_var(t) && dead_after(p, block, i + 2, t, live)) {
          Instr sub = *a;
          sub.args = {*into, Operand::var(t)};
          if (x == *into) {
            code[i] = sub;
            erase(i + 1, 2);
          } else if (accepts(Op::SetVariable, 1, x) && !reads_var(*a, into->value)) {
            Instr set = *a;
            set.op = Op::SetVariable;
            set.args = {*into, x};
            code[i] = set;
            code[i + 1] = sub;
            erase(i + 2, 1);
          } else {
            continue;
          }
          changed = true;
          continue;
        }
      }
      // `t op= V; V = t` (op commutes) -> `V op= t`.
      if (commutes(a->op) && a->args[1].is_var()) {
        auto into = copies_t_into(n1);
        if (into && *into == a->args[1] && dead_after(p, block, i + 1, t, live)) {
          Instr op = *a;
          op.args = {*into, Operand::var(t)};
          code[i] = op;
          erase(i + 1, 1);
          changed = true;
          continue;
        }
      }
      // `t = X; V op= t` with t read nowhere after -> `V op= X`.
      if (a->op == Op::SetVariable && n1 && is_op(*n1, n1->op) && arithmetic_op(n1->op) && n1->args[1].is_var(t) &&
          !n1->args[0].is_var(t) && !a->args[1].is_var(t) && accepts(n1->op, 1, a->args[1]) &&
          dead_after(p, block, i + 1, t, live)) {
        code[i + 1].args[1] = a->args[1];
        erase(i, 1);
        changed = true;
        continue;
      }
    }
  }
  return changed;
}

}  // namespace

void compute_into_targets(Program& p) {
  auto calls = call_effects(p);
  for (auto& f : p.functions) {
    if (f.blocks.empty()) continue;
    // Each rewrite can make the next one possible (`t = X; t += V; V = t`
    // becomes `t = X; V += t`, then `V += X`).
    for (int round = 0; round < 4 && coalesce_in(p, f, calls); ++round) {
    }
  }
}

}  // namespace rcxc::ir
