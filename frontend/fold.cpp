#include "frontend/fold.h"

#include "frontend/frontend.h"
#include "frontend/token.h"

namespace rcxc::frontend {

using namespace ast;

std::optional<std::int16_t> fold_binary(BinaryOp op, std::int16_t a, std::int16_t b) {
  const std::int32_t x = a, y = b;
  switch (op) {
    case BinaryOp::Mul: return wrap16(x * y);
    case BinaryOp::Div:
      if (y == 0) return std::nullopt;
      return wrap16(x / y);  // -32768 / -1 wraps to -32768
    case BinaryOp::Mod:
      if (y == 0) return std::nullopt;
      return wrap16(x % y);
    case BinaryOp::Add: return wrap16(x + y);
    case BinaryOp::Sub: return wrap16(x - y);
    // As the code the compiler emits for a shift computes it (the RCX has
    // no shift instruction): >> shifts zeros in, a negative count shifts
    // nothing, a count of 16 or more shifts everything out.
    case BinaryOp::Shl:
      if (y < 0) return a;
      return y >= 16 ? std::int16_t{0} : wrap16(static_cast<std::int64_t>(static_cast<std::uint16_t>(a)) << y);
    case BinaryOp::Shr:
      if (y < 0) return a;
      return y >= 16 ? std::int16_t{0} : wrap16(static_cast<std::uint16_t>(a) >> y);
    case BinaryOp::Lt: return static_cast<std::int16_t>(x < y);
    case BinaryOp::Le: return static_cast<std::int16_t>(x <= y);
    case BinaryOp::Gt: return static_cast<std::int16_t>(x > y);
    case BinaryOp::Ge: return static_cast<std::int16_t>(x >= y);
    case BinaryOp::Eq: return static_cast<std::int16_t>(x == y);
    case BinaryOp::Ne: return static_cast<std::int16_t>(x != y);
    case BinaryOp::BitAnd: return wrap16(x & y);
    case BinaryOp::BitXor: return wrap16(x ^ y);
    case BinaryOp::BitOr: return wrap16(x | y);
    case BinaryOp::LogAnd: return static_cast<std::int16_t>(x && y);
    case BinaryOp::LogOr: return static_cast<std::int16_t>(x || y);
  }
  return std::nullopt;
}

std::optional<std::int16_t> fold_unary(UnaryOp op, std::int16_t a) {
  switch (op) {
    case UnaryOp::Negate: return wrap16(-static_cast<std::int32_t>(a));
    case UnaryOp::BitNot: return wrap16(~static_cast<std::int32_t>(a));
    case UnaryOp::LogNot: return static_cast<std::int16_t>(a == 0);
    case UnaryOp::Plus: return a;
    case UnaryOp::Abs: return a == -32768 ? std::int16_t{32767} : static_cast<std::int16_t>(a < 0 ? -a : a);
    case UnaryOp::Sign: return static_cast<std::int16_t>((a > 0) - (a < 0));
    default: return std::nullopt;
  }
}

namespace {

std::optional<std::int64_t> exact_rec(const Expr& e, int& budget) {
  // Far past what 16-bit operands can reach after a few hundred nodes, and
  // no int64 overflow: each step is bounded before it is taken.
  constexpr std::int64_t kLimit = std::int64_t{1} << 40;
  if (--budget < 0) return std::nullopt;
  if (const auto* lit = as<IntLit>(e)) {
    if (lit->value >= kLiteralPastRange) return std::nullopt;
    return lit->value;
  }
  if (const auto* u = as<Unary>(e)) {
    if (u->op != UnaryOp::Negate && u->op != UnaryOp::Plus) return std::nullopt;
    auto a = exact_rec(*u->operand, budget);
    if (!a) return std::nullopt;
    return u->op == UnaryOp::Negate ? -*a : *a;
  }
  const auto* b = as<Binary>(e);
  if (!b) return std::nullopt;
  auto x = exact_rec(*b->lhs, budget);
  if (!x) return std::nullopt;
  auto y = exact_rec(*b->rhs, budget);
  if (!y) return std::nullopt;
  std::int64_t r = 0;
  switch (b->op) {
    case BinaryOp::Add: r = *x + *y; break;
    case BinaryOp::Sub: r = *x - *y; break;
    case BinaryOp::Mul:
      if ((*x != 0 && (*y > kLimit || *y < -kLimit)) || (*y != 0 && (*x > kLimit || *x < -kLimit))) return std::nullopt;
      r = *x * *y;
      break;
    case BinaryOp::Div:
    case BinaryOp::Mod: {
      auto q = exact_divide(b->op, *x, *y);
      if (!q) return std::nullopt;
      r = *q;
      break;
    }
    default: return std::nullopt;
  }
  if (r > kLimit || r < -kLimit) return std::nullopt;
  return r;
}

std::optional<std::int16_t> fold_rec(const Expr& e, Diagnostics* diags) {
  if (const auto* lit = as<IntLit>(e)) return wrap16(lit->value);
  if (const auto* u = as<Unary>(e)) {
    auto a = fold_rec(*u->operand, diags);
    return a ? fold_unary(u->op, *a) : std::nullopt;
  }
  if (const auto* b = as<Binary>(e)) {
    auto x = fold_rec(*b->lhs, diags);
    // && and || need only the left side when it decides.
    if (x && b->op == BinaryOp::LogAnd && *x == 0) return std::int16_t{0};
    if (x && b->op == BinaryOp::LogOr && *x != 0) return std::int16_t{1};
    auto y = fold_rec(*b->rhs, diags);
    if (!x || !y) return std::nullopt;
    auto r = fold_binary(b->op, *x, *y);
    if (!r && diags) diags->error(e.span, "division by zero in a constant expression");
    return r;
  }
  if (const auto* c = as<Conditional>(e)) {
    auto cond = fold_rec(*c->cond, diags);
    if (!cond) return std::nullopt;
    return fold_rec(*cond ? *c->then_value : *c->else_value, diags);
  }
  if (const auto* sa = as<SourceArg>(e)) {
    if (sa->or_constant_byte)
      if (auto k = fold_rec(*sa->operand, nullptr)) return static_cast<std::int16_t>(*k & 0xff);
    const auto* src = as<Source>(*sa->operand);
    if (!src) {
      if (diags) diags->error(sa->operand->span, "__source_arg needs a source expression such as SENSOR_1");
      return std::nullopt;
    }
    auto type = fold_rec(*src->type, diags);
    auto arg = fold_rec(*src->arg, diags);
    if (!type || !arg) return std::nullopt;
    if (sa->type_required && *sa->type_required != *type) {
      if (diags)
        diags->error(sa->operand->span, "argument must be a " +
                                            std::string(rcx::source_name(*sa->type_required)) + " source");
      return std::nullopt;
    }
    return arg;
  }
  return e.constant;  // names (e.g. substituted constants) keep what sema found
}

}  // namespace

std::optional<std::int16_t> fold_constant(const Expr& e, Diagnostics* diags) { return fold_rec(e, diags); }

namespace {

struct NqcFolder {
  const NameBinding& bound;
  std::optional<std::int16_t> task_id;
  bool task_id_constant;

  NqcConstant operator()(const Expr& e) const {
    if (const auto* lit = as<IntLit>(e)) return {true, wrap16(lit->value)};
    if (const auto* n = as<Name>(e)) {
      const Expr* to = bound(*n);
      return to ? (*this)(*to) : NqcConstant{};
    }
    if (as<TaskId>(e)) return task_id_constant ? NqcConstant{true, task_id} : NqcConstant{};
    if (const auto* t = as<TypeOf>(e)) return {true, static_cast<std::int16_t>((*this)(*t->operand).constant ? 2 : 0)};
    if (const auto* u = as<Unary>(e)) return unary(*u);
    if (const auto* b = as<Binary>(e)) return binary(*b);
    if (const auto* c = as<Conditional>(e)) return conditional(*c);
    // A source is constant when sema folded it (`@0x20005`, __source_arg);
    // nqc reads `@(...)` when it parses it, before __taskid is known.
    if (e.constant && (as<Source>(e) || as<SourceArg>(e))) return {true, e.constant};
    return {};
  }

  NqcConstant unary(const Unary& u) const {
    if (u.op == UnaryOp::PreInc || u.op == UnaryOp::PreDec || u.op == UnaryOp::PostInc || u.op == UnaryOp::PostDec)
      return {};
    NqcConstant a = (*this)(*u.operand);
    if (a.value) a.value = fold_unary(u.op, *a.value);
    return a;
  }

  NqcConstant binary(const Binary& b) const {
    NqcConstant l = (*this)(*b.lhs), r = (*this)(*b.rhs);
    auto is_zero = [](const NqcConstant& c) { return c.value && *c.value == 0; };
    auto is_true = [](const NqcConstant& c) { return c.value && *c.value != 0; };
    if (b.op == BinaryOp::LogAnd && (is_zero(l) || is_zero(r))) return {true, std::int16_t{0}};
    if (b.op == BinaryOp::LogOr && (is_true(l) || is_true(r))) return {true, std::int16_t{1}};
    if (!l.constant || !r.constant) return {};
    if (!l.value || !r.value) return {true, std::nullopt};
    return {true, fold_binary(b.op, *l.value, *r.value)};
  }

  NqcConstant conditional(const Conditional& c) const {
    NqcConstant k = (*this)(*c.cond);
    if (k.value) return (*this)(*k.value != 0 ? *c.then_value : *c.else_value);
    if (k.constant && (*this)(*c.then_value).constant && (*this)(*c.else_value).constant) return {true, std::nullopt};
    return {};
  }
};

}  // namespace

NqcConstant nqc_constant(const Expr& e, const NameBinding& bound, std::optional<std::int16_t> task_id,
                         bool task_id_constant) {
  return NqcFolder{bound, task_id, task_id_constant}(e);
}

std::optional<std::int64_t> exact_divide(BinaryOp op, std::int64_t x, std::int64_t y) {
  if (y == 0) return std::nullopt;
  return op == BinaryOp::Div ? x / y : x % y;
}

std::optional<std::int64_t> exact_constant(const Expr& e) {
  int budget = 256;
  return exact_rec(e, budget);
}

}  // namespace rcxc::frontend
