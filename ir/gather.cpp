// Constant arithmetic on one variable gathered into one step (see passes.h).
#include <iterator>
#include <optional>
#include <vector>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

using rcx::Op;

// `d op= constant`: what two neighbours must both be to become one.
struct ConstantStep {
  VarId var;
  Op op;
  int value;
};

std::optional<ConstantStep> constant_step(const Instr& in) {
  if (in.raw || in.args.size() != 2 || !in.args[0].is_var() || !in.args[1].is_imm()) return std::nullopt;
  switch (in.op) {
    case Op::AddToVariable: case Op::SubtractFromVariable: case Op::MultiplyVariable:
    case Op::DivideVariable: case Op::AndVariable: case Op::OrVariable:
      return ConstantStep{in.args[0].value, in.op, in.args[1].value};
    default: return std::nullopt;
  }
}

bool adds(Op op) { return op == Op::AddToVariable || op == Op::SubtractFromVariable; }
int signed_term(Op op, int value) { return op == Op::SubtractFromVariable ? -value : value; }

// `d += k` as it reads best: a negative k subtracted (but -32768, which
// has no positive twin).
ConstantStep sum_step(VarId d, int k) {
  if (k < 0 && k != -32768) return {d, Op::SubtractFromVariable, -k};
  return {d, Op::AddToVariable, k};
}

// The step that does what `a` then `b` do (the same variable); nullopt
// where no one step does. The firmware's + - * wrap at 16 bits, so sums
// and products of the constants gather exactly; & and | always do; two
// divisions by positive constants are one by their product (truncating
// division), while it fits.
std::optional<ConstantStep> combined(const ConstantStep& a, const ConstantStep& b) {
  if (adds(a.op) && adds(b.op))
    return sum_step(a.var, wrap16(static_cast<long>(signed_term(a.op, a.value)) + signed_term(b.op, b.value)));
  if (a.op != b.op) return std::nullopt;
  switch (a.op) {
    case Op::MultiplyVariable: case Op::AndVariable: case Op::OrVariable:
      return ConstantStep{a.var, a.op, *arithmetic(a.op, a.value, b.value)};
    case Op::DivideVariable:
      if (a.value <= 0 || b.value <= 0 || static_cast<long>(a.value) * b.value > 32767) return std::nullopt;
      return ConstantStep{a.var, a.op, a.value * b.value};
    default: return std::nullopt;
  }
}

// Neighbouring constant steps on one variable, as one: `x - 100 - 10` is
// `x -= 110`. A global then skips a value between, which another task
// could only have seen for an instruction's time.
void merge_neighbours(std::vector<Instr>& code) {
  std::vector<Instr> out;
  out.reserve(code.size());
  for (auto& in : code) {
    auto step = constant_step(in);
    auto before = step && !out.empty() ? constant_step(out.back()) : std::nullopt;
    if (before && before->var == step->var) {
      if (auto c = combined(*before, *step); c && accepts(c->op, 1, Operand::imm(c->value))) {
        if (leaves_unchanged(c->op, c->value)) {
          out.pop_back();
        } else {
          out.back().op = c->op;
          out.back().args[1] = Operand::imm(c->value);
        }
        continue;
      }
    }
    out.push_back(std::move(in));
  }
  code = std::move(out);
}

// Whether `in` is `d += c`, `d -= c`, `d += v` or `d -= v` (v not d): a
// term of a sum computed into d.
bool sum_term(const Instr& in, VarId d) {
  if (in.raw || !adds(in.op) || in.args.size() != 2 || !in.args[0].is_var(d)) return false;
  return in.args[1].is_imm() || (in.args[1].is_var() && !in.args[1].is_var(d));
}

// `t = c; t += v; ... t ± c2` (a sum that starts with a constant: `2 + b +
// 5`), code[at] to code[end], as `t = v; ... t ± (c + c2)`, the variables
// added in the order they were: one instruction per constant less. Only
// where no other task reads t, which would see it hold v, a value the
// source never gives it (`other_tasks`: a global is read by none when
// one task runs). nullopt where nothing is saved.
std::optional<std::vector<Instr>> sum_started_by_constant(const std::vector<Instr>& code, std::size_t at,
                                                         std::size_t end) {
  const Instr& set = code[at];
  VarId d = set.args[0].value;
  long constant = set.args[1].value;
  int constants = 0;
  std::vector<const Instr*> variables;
  for (std::size_t i = at + 1; i < end; ++i) {
    if (code[i].args[1].is_imm()) {
      constant += signed_term(code[i].op, code[i].args[1].value);
      ++constants;
    } else {
      variables.push_back(&code[i]);
    }
  }
  int k = wrap16(constant);
  if (variables.empty() || variables.front()->op != Op::AddToVariable || (constants == 0 && k != 0))
    return std::nullopt;
  std::vector<Instr> out;
  out.emplace_back(Op::SetVariable, Operands{Operand::var(d), variables.front()->args[1]}, false, set.span);
  for (std::size_t i = 1; i < variables.size(); ++i) out.push_back(*variables[i]);
  if (k != 0) {
    ConstantStep rest = sum_step(d, k);
    out.emplace_back(rest.op, Operands{Operand::var(d), Operand::imm(rest.value)}, false, set.span);
  }
  return out;
}

void gather_sums(std::vector<Instr>& code, const std::vector<Var>& vars, bool other_tasks) {
  std::vector<Instr> out;
  out.reserve(code.size());
  for (std::size_t i = 0; i < code.size();) {
    const Instr& set = code[i];
    if (!set.raw && set.op == Op::SetVariable && set.args.size() == 2 && set.args[0].is_var() &&
        set.args[1].is_imm() &&
        (!other_tasks || vars[static_cast<std::size_t>(set.args[0].value)].kind != VarKind::Global)) {
      std::size_t end = i + 1;
      while (end < code.size() && sum_term(code[end], set.args[0].value)) ++end;
      if (auto sum = sum_started_by_constant(code, i, end)) {
        std::move(sum->begin(), sum->end(), std::back_inserter(out));
        i = end;
        continue;
      }
    }
    out.push_back(std::move(code[i]));
    ++i;
  }
  code = std::move(out);
}

}  // namespace

void gather_constant_arithmetic(Function& f, const std::vector<Var>& vars, bool other_tasks) {
  for (auto& b : f.blocks) {
    merge_neighbours(b.instrs);
    gather_sums(b.instrs, vars, other_tasks);
  }
}

}  // namespace rcxc::ir
