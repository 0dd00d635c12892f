// Computing into the assigned variable instead of into a temporary that is
// then copied (see passes.h).
#include <optional>
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

bool adds_or_subtracts(const Instr& in) {
  return is_op(in, Op::AddToVariable) || is_op(in, Op::SubtractFromVariable);
}

// What `t = X; t ±= Y...; V ±= t` at code[i] becomes, and where the code
// after it starts.
struct Spread {
  std::vector<Instr> instrs;
  std::size_t next = 0;
};

std::optional<Spread> spread_sum_into(const std::vector<Instr>& code, std::size_t i, const std::vector<bool>& dies) {
  const Operand t = code[i].args[0];
  std::size_t k = i + 1;
  while (k < code.size() && adds_or_subtracts(code[k]) && code[k].args[0] == t && !(code[k].args[1] == t)) ++k;
  if (k == i + 1 || k == code.size()) return std::nullopt;
  const Instr& use = code[k];
  if (!adds_or_subtracts(use) || !(use.args[1] == t) || use.args[0] == t || !dies[k]) return std::nullopt;
  const Operand v = use.args[0];
  auto flipped = [](Op op) { return op == Op::AddToVariable ? Op::SubtractFromVariable : Op::AddToVariable; };
  Spread s;
  Instr first = use;
  first.args = {v, code[i].args[1]};
  if (!accepts(first.op, 1, first.args[1])) return std::nullopt;
  s.instrs.push_back(std::move(first));
  for (std::size_t j = i + 1; j < k; ++j) {
    if (code[j].args[1] == v) return std::nullopt;
    Instr in = code[j];
    in.args[0] = v;
    if (use.op == Op::SubtractFromVariable) in.op = flipped(in.op);
    if (!accepts(in.op, 1, in.args[1])) return std::nullopt;
    s.instrs.push_back(std::move(in));
  }
  s.next = k + 1;
  return s;
}

// One scan of a function; returns whether anything changed.
bool coalesce_in(const Program& p, Function& f, const CallEffects& calls, LivenessCache& cache, bool other_tasks) {
  // A function without a candidate block needs no liveness.
  std::vector<bool> candidate(f.blocks.size());
  bool any = false;
  for (std::size_t b = 0; b < f.blocks.size(); ++b) any |= candidate[b] = has_candidate(p, f.blocks[b]);
  if (!any) return false;
  const Liveness& L = cache.of(p, f, calls);
  bool changed = false;
  auto private_var = [&](const Operand& o) {
    return o.is_var() && !shared_between_tasks(p.vars[static_cast<std::size_t>(o.value)]);
  };
  // A rewrite into V of more than one instruction shows another task a
  // value V never takes in the source (`v = x - v` as `v -= x; v *= -1`
  // holds v - x for an instruction; a task waiting for v < 0 would see
  // it): only into what no other task can read.
  auto steps_may_show = [&](const Operand& v) { return other_tasks && !private_var(v); };
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
        if (into && *into == v && !x.is_var(t) && !(x == v) && !reads_random(x) && !steps_may_show(v) &&
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
        if (into && !x.is_var(t) && (x == *into || (accepts(Op::SetVariable, 1, x) && !steps_may_show(*into)))) {
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
      // `t = X; t ±= Y...; V ±= t` with t read nowhere after -> `V ±= X;
      // V ±= Y...` (V - (X + Y) is V - X - Y): one instruction less. No Y
      // may be V, which changes before they are read; X is read first.
      if (a->op == Op::SetVariable && !a->args[1].is_var(t)) {
        auto spread = spread_sum_into(code, i, dies);
        if (spread && !steps_may_show(spread->instrs.front().args[0])) {
          for (auto& in : spread->instrs) out.push_back(std::move(in));
          i = spread->next;
          changed = true;
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
  const bool other_tasks = runs_several_tasks(p);
  LivenessCache own;
  for (auto& f : p.functions) {
    if (f.blocks.empty()) continue;
    // Each rewrite can make the next one possible (`t = X; t += V; V = t`
    // becomes `t = X; V += t`, then `V += X`).
    for (int round = 0; round < 4 && coalesce_in(p, f, calls, cache ? *cache : own, other_tasks); ++round) {
    }
  }
}

}  // namespace rcxc::ir
