#include "frontend/ranges.h"

#include <algorithm>
#include <map>
#include <string>

#include "frontend/fold.h"

namespace rcxc::frontend {
namespace {

using namespace ast;

struct Range {
  std::string_view mnemonic;
  std::string_view operand;
  int lo, hi;
  std::string_view meaning = {};
  std::string_view effect = {};
};

// From the seed's operand descriptions.
constexpr Range kRanges[] = {
    {"sound", "sound", 0, 5},        {"timerclr", "timer", 0, 3},      {"sensclr", "sensor", 0, 2},
    {"senstype", "sensor", 0, 2},    {"senstype", "type", 0, 4},       {"sensmode", "sensor", 0, 2},
    {"settime", "hours", 0, 23},     {"settime", "minutes", 0, 59},    {"txrange", "range", 0, 1},
    {"sleepdelay", "minutes", 0, 99}, {"program", "program", 0, 4},
    {"pwr", "source", 0, 7, "the power level", "the RCX ignores the command"},
    // 16 bits, signed: Wait(60000) is -5536 to the brick, which then does
    // not wait at all (a wait of 600 s is Wait(30000) twice).
    {"wait", "source", 0, 32767, "the time in 1/100 s", "the RCX does not wait (a wait is at most 327.67 s)"},
    {"call", "subroutine", 0, 7},    {"start", "task", 0, 9},          {"stop", "task", 0, 9},
};

using Bindings = std::map<SymbolId, std::int16_t>;

std::optional<std::int16_t> fold_with(const Expr& e, const Bindings& b) {
  if (const auto* n = as<Name>(e)) {
    auto it = b.find(n->symbol);
    if (it != b.end()) return it->second;
    return e.constant;
  }
  if (const auto* u = as<Unary>(e)) {
    auto a = fold_with(*u->operand, b);
    return a ? fold_unary(u->op, *a) : std::nullopt;
  }
  if (const auto* x = as<Binary>(e)) {
    auto l = fold_with(*x->lhs, b);
    auto r = fold_with(*x->rhs, b);
    return l && r ? fold_binary(x->op, *l, *r) : std::nullopt;
  }
  if (const auto* c = as<Conditional>(e)) {
    auto cond = fold_with(*c->cond, b);
    if (!cond) return std::nullopt;
    return fold_with(*cond ? *c->then_value : *c->else_value, b);
  }
  return e.constant;
}

class RangeCheck {
 public:
  RangeCheck(const Program& p, SourceSpan call, Diagnostics& d) : prog_(p), call_(call), diags_(d) {}

  void function(const Function& f, const std::vector<Expr>& args, const Bindings& outer, int depth) {
    if (depth > 16 || args.size() != f.params.size()) return;
    Bindings b;
    for (std::size_t i = 0; i < args.size(); ++i) {
      const Param& p = f.params[i];
      if (p.symbol == kNoSymbol || (p.kind != ParamKind::Const && p.kind != ParamKind::ConstReference)) continue;
      if (auto v = fold_with(args[i], outer)) b[p.symbol] = *v;
    }
    const std::string& name = depth == 0 ? f.name : outer_name_;
    if (depth == 0) outer_name_ = f.name;
    stmt(f.body, b, depth, name);
  }

 private:
  const Program& prog_;
  SourceSpan call_;
  Diagnostics& diags_;
  std::string outer_name_;

  void stmt(const Stmt& s, const Bindings& b, int depth, const std::string& name) {
    std::visit(
        [&](const auto& n) {
          using N = std::decay_t<decltype(n)>;
          if constexpr (std::is_same_v<N, Block>) {
            for (const auto& c : n.stmts) stmt(c, b, depth, name);
          } else if constexpr (std::is_same_v<N, If>) {
            stmt(*n.then_branch, b, depth, name);
            if (n.else_branch) stmt(**n.else_branch, b, depth, name);
          } else if constexpr (std::is_same_v<N, ExprStmt>) {
            const auto* c = as<Call>(n.expr);
            if (c && c->symbol != kNoSymbol && prog_.symbol(c->symbol).kind == SymbolKind::Function)
              function(prog_.functions.at(prog_.symbol(c->symbol).index), c->args, b, depth + 1);
          } else if constexpr (std::is_same_v<N, Asm>) {
            for (const auto& item : n.items)
              if (const auto* in = std::get_if<AsmInstr>(&item)) instr(*in, b, name);
          }
        },
        s.node);
  }

  void instr(const AsmInstr& in, const Bindings& b, const std::string& name) {
    if (!in.op) return;
    std::size_t i = 0;
    for (const auto& o : rcx::info(*in.op).operands) {
      if (o.role == rcx::Role::Argument) continue;
      if (i >= in.operands.size()) return;
      const Expr& e = in.operands[i++];
      auto range = operand_range(in.mnemonic, o.name);
      if (!range || e.constant) continue;  // constant operands were checked where they are written
      auto v = fold_with(e, b);
      if (!v || (*v >= range->lo && *v <= range->hi)) continue;
      auto& d = diags_.warning(call_, WarningKind::Range, "'" + name + "' passes " + std::to_string(*v) + " as " +
                                          describe_operand(in.mnemonic, o.name, *range) + outside_range(*range));
      d.notes.push_back({e.span, "the operand is here"});
    }
  }
};

bool has_ranged_operand(const AsmInstr& in) {
  if (!in.op) return false;
  std::size_t i = 0;
  for (const auto& o : rcx::info(*in.op).operands) {
    if (o.role == rcx::Role::Argument) continue;
    if (i >= in.operands.size()) return false;
    if (!in.operands[i++].constant && operand_range(in.mnemonic, o.name)) return true;
  }
  return false;
}

// Whether RangeCheck::stmt could warn anywhere under `s`, at any depth (it
// follows the same statements and calls).
bool may_warn(const Program& prog, const Stmt& s, RangeMemo& memo);

bool function_may_warn(const Program& prog, std::size_t index, RangeMemo& memo) {
  if (memo.may_warn.size() != prog.functions.size()) memo.may_warn.assign(prog.functions.size(), -1);
  if (memo.may_warn[index] < 0) {
    memo.may_warn[index] = 1;  // while it is being looked at: a call cycle may warn (the walk decides)
    memo.may_warn[index] = may_warn(prog, prog.functions[index].body, memo) ? 1 : 0;
  }
  return memo.may_warn[index] == 1;
}

bool may_warn(const Program& prog, const Stmt& s, RangeMemo& memo) {
  return std::visit(
      [&](const auto& n) {
        using N = std::decay_t<decltype(n)>;
        if constexpr (std::is_same_v<N, Block>) {
          return std::any_of(n.stmts.begin(), n.stmts.end(), [&](const Stmt& c) { return may_warn(prog, c, memo); });
        } else if constexpr (std::is_same_v<N, If>) {
          return may_warn(prog, *n.then_branch, memo) || (n.else_branch && may_warn(prog, **n.else_branch, memo));
        } else if constexpr (std::is_same_v<N, ExprStmt>) {
          const auto* c = as<Call>(n.expr);
          return c && c->symbol != kNoSymbol && prog.symbol(c->symbol).kind == SymbolKind::Function &&
                 function_may_warn(prog, prog.symbol(c->symbol).index, memo);
        } else if constexpr (std::is_same_v<N, Asm>) {
          return std::any_of(n.items.begin(), n.items.end(), [](const AsmItem& item) {
            const auto* in = std::get_if<AsmInstr>(&item);
            return in && has_ranged_operand(*in);
          });
        } else {
          return false;
        }
      },
      s.node);
}

}  // namespace

std::optional<OperandRange> operand_range(std::string_view mnemonic, std::string_view operand) {
  for (const auto& r : kRanges)
    if (r.mnemonic == mnemonic && r.operand == operand) return OperandRange{r.lo, r.hi, r.meaning, r.effect};
  return std::nullopt;
}

std::string describe_operand(std::string_view mnemonic, std::string_view operand, const OperandRange& range) {
  std::string text = "operand '" + std::string(operand) + "'";
  if (!range.meaning.empty()) text += " (" + std::string(range.meaning) + ")";
  return text + " of '" + std::string(mnemonic) + "'";
}

std::string outside_range(const OperandRange& range) {
  std::string text = ", outside the RCX's range " + std::to_string(range.lo) + ".." + std::to_string(range.hi);
  if (!range.effect.empty()) text += "; " + std::string(range.effect);
  return text;
}

void check_call_ranges(const Program& program, const Function& f, const std::vector<Expr>& args, SourceSpan call,
                       Diagnostics& diags, RangeMemo& memo) {
  auto index = static_cast<std::size_t>(&f - program.functions.data());
  if (index < program.functions.size() && !function_may_warn(program, index, memo)) return;
  RangeCheck(program, call, diags).function(f, args, {}, 0);
}

}  // namespace rcxc::frontend
