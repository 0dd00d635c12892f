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

// Whether some instruction of `b` writes a temporary or local that the
// next one reads as its second operand only: every rewrite below ends so,
// and a block without one is left as it is.
bool has_candidate(const Program& p, const Block& b) {
  for (std::size_t i = 0; i + 1 < b.instrs.size(); ++i) {
    const Instr& a = b.instrs[i];
    const Instr& n = b.instrs[i + 1];
    if (a.raw || n.raw || a.args.empty() || !a.args[0].is_var() || n.args.size() != 2) continue;
    VarId t = a.args[0].value;
    if (p.vars[static_cast<std::size_t>(t)].kind != VarKind::Global && n.args[1].is_var(t) && !n.args[0].is_var(t))
      return true;
  }
  return false;
}

// For each instruction of `block`, whether the variable it reads as its
// second operand (when that is a variable) is read nowhere after it:
// `live` is the block's live-out.
std::vector<bool> second_operand_dies(const Program& p, const Block& block, const CallEffects& calls, VarSet live) {
  for (VarId v : reads_of(block.term)) live.add(v);
  std::vector<bool> dies(block.instrs.size(), false);
  for (std::size_t k = block.instrs.size(); k-- > 0;) {
    const Instr& in = block.instrs[k];
    if (!in.raw && in.args.size() == 2 && in.args[1].is_var()) dies[k] = !live.has(in.args[1].value);
    step_back(p, in, calls, live);
  }
  return dies;
}

// One scan of a function; returns whether anything changed.
bool coalesce_in(const Program& p, Function& f, const CallEffects& calls, LivenessCache& cache) {
  // A function without a candidate block needs no liveness.
  std::vector<bool> candidate(f.blocks.size());
  bool any = false;
  for (std::size_t b = 0; b < f.blocks.size(); ++b) any |= candidate[b] = has_candidate(p, f.blocks[b]);
  if (!any) return false;
  const Liveness& L = cache.of(p, f, calls);
  bool changed = false;
  auto private_var = [&](const Operand& o) {
    if (!o.is_var()) return false;
    const Var& v = p.vars[static_cast<std::size_t>(o.value)];
    return v.kind != VarKind::Global && !v.slot;
  };
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    if (!candidate[b]) continue;
    Block& block = f.blocks[b];
    const auto& code = block.instrs;
    std::vector<bool> dies = second_operand_dies(p, block, calls, L.live_out[b]);
    std::vector<Instr> out;
    out.reserve(code.size());
    // `t = X; V op= t` at the end of `out`, t read nowhere after -> `V op= X`.
    auto fold_set_into_last = [&]() {
      if (out.size() < 2) return;
      Instr& set = out[out.size() - 2];
      Instr& use = out.back();
      if (!is_op(set, Op::SetVariable) || !is_op(use, use.op) || !arithmetic_op(use.op)) return;
      const Operand& t = set.args[0];
      if (!private_var(t) || !(use.args[1] == t) || use.args[0] == t || set.args[1] == t ||
          !accepts(use.op, 1, set.args[1]))
        return;
      use.args[1] = set.args[1];
      out.erase(out.end() - 2);
      changed = true;
    };
    for (std::size_t i = 0; i < code.size();) {
      auto at = [&](std::size_t k) -> const Instr* { return k < code.size() ? &code[k] : nullptr; };
      const Instr* a = at(i);
      const Instr* n1 = at(i + 1);
      const Instr* n2 = at(i + 2);
      auto keep = [&]() {
        out.push_back(*a);
        ++i;
      };
      if (!is_op(*a, a->op) || !private_var(a->args[0])) {
        keep();
        continue;
      }
      VarId t = a->args[0].value;
      // Whether `in` (instruction k) copies t into another variable, t
      // read nowhere after it.
      auto copies_t_into = [&](const Instr* in, std::size_t k) -> std::optional<Operand> {
        if (!in || !is_op(*in, Op::SetVariable) || !in->args[1].is_var(t) || in->args[0].is_var(t) || !dies[k])
          return std::nullopt;
        return in->args[0];
      };

      // `t = X; t -= V; V = t` -> `V -= X; V *= -1`.
      if (a->op == Op::SetVariable && n1 && is_op(*n1, Op::SubtractFromVariable) && n1->args[0].is_var(t) &&
          n1->args[1].is_var()) {
        Operand x = a->args[1], v = n1->args[1];
        auto into = copies_t_into(n2, i + 2);
        if (into && *into == v && !x.is_var(t) && !(x == v) && !reads_random(x) &&
            accepts(Op::SubtractFromVariable, 1, x)) {
          Instr sub = *n1, neg = *n1;
          sub.args = {v, x};
          neg.op = Op::MultiplyVariable;
          neg.args = {v, Operand::imm(-1)};
          out.push_back(std::move(sub));
          out.push_back(std::move(neg));
          i += 3;
          changed = true;
          continue;
        }
      }
      // `t -= X; t *= -1; V = t` (t = X - t) -> `V -= t` when X is V,
      // else `V = X; V -= t`.
      if (a->op == Op::SubtractFromVariable && n1 && is_op(*n1, Op::MultiplyVariable) && n1->args[0].is_var(t) &&
          n1->args[1] == Operand::imm(-1)) {
        Operand x = a->args[1];
        auto into = copies_t_into(n2, i + 2);
        if (into && !x.is_var(t) && (x == *into || accepts(Op::SetVariable, 1, x))) {
          Instr sub = *a;
          sub.args = {*into, Operand::var(t)};
          if (!(x == *into)) {
            Instr set = *a;
            set.op = Op::SetVariable;
            set.args = {*into, x};
            out.push_back(std::move(set));
          }
          out.push_back(std::move(sub));
          i += 3;
          changed = true;
          continue;
        }
      }
      // `t op= V; V = t` (op commutes) -> `V op= t`, and then perhaps
      // `V op= X` when t was just set to X.
      if (commutes(a->op) && a->args[1].is_var()) {
        auto into = copies_t_into(n1, i + 1);
        if (into && *into == a->args[1]) {
          Instr op = *a;
          op.args = {*into, Operand::var(t)};
          out.push_back(std::move(op));
          i += 2;
          changed = true;
          fold_set_into_last();
          continue;
        }
      }
      // `t = X; V op= t` with t read nowhere after -> `V op= X`.
      if (a->op == Op::SetVariable && n1 && n1->args.size() == 2 && n1->args[1].is_var(t) && dies[i + 1]) {
        out.push_back(*a);
        out.push_back(*n1);
        i += 2;
        fold_set_into_last();
        continue;
      }
      keep();
    }
    if (out.size() != code.size()) block.instrs = std::move(out);
  }
  return changed;
}

}  // namespace

void compute_into_targets(Program& p, LivenessCache* cache) {
  auto calls = call_effects(p);
  LivenessCache own;
  for (auto& f : p.functions) {
    if (f.blocks.empty()) continue;
    // Each rewrite can make the next one possible (`t = X; t += V; V = t`
    // becomes `t = X; V += t`, then `V += X`).
    for (int round = 0; round < 4 && coalesce_in(p, f, calls, cache ? *cache : own); ++round) {
    }
  }
}

}  // namespace rcxc::ir
