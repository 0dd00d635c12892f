// Constant arithmetic of the target: 16-bit two's complement with wrap-around,
// shared by semantic analysis and frontend::fold_constant.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "frontend/ast.h"

namespace rcxc::frontend {

inline std::int16_t wrap16(std::int64_t v) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(static_cast<std::uint64_t>(v) & 0xFFFFu));
}

// The value the brick computes, except that division or modulo by zero is
// nullopt (in a constant expression the caller reports it; at run time the
// firmware leaves the dividend).
std::optional<std::int16_t> fold_binary(ast::BinaryOp op, std::int16_t a, std::int16_t b);
// Pre/post increment and decrement are never constant: nullopt.
std::optional<std::int16_t> fold_unary(ast::UnaryOp op, std::int16_t a);

// The value of constant arithmetic as written, in wide integers: literals,
// parentheses, unary - and +, and + - * / % of those (what a C compiler,
// or nqc in 32 bits, computes for `60 * 1000 / 10`). nullopt for anything
// else, for a division by zero, and past a few hundred nodes (the caller
// asks at each division, so the work stays linear in the program).
std::optional<std::int64_t> exact_constant(const ast::Expr& e);
// x / y or x % y (`op` Div or Mod) in wide integers, truncating as C does;
// nullopt when y is 0. exact_constant's division, and the one the wrapped
// operand warning compares the brick's 16-bit result with.
std::optional<std::int64_t> exact_divide(ast::BinaryOp op, std::int64_t x, std::int64_t y);

// Whether nqc takes `e` as a constant expression, which is what `__type(e)`
// reports (2 when it does, 0 otherwise), and its value when that is known.
// nqc's rule, not the brick's arithmetic: `x && 0` and `x || 1` count
// (nqc folds them whatever x is), `x * 0` and a timer do not. `bound` says
// what a name stands for (a substituted `const` parameter's argument;
// nullptr for a variable); `task_id` is __taskid's value when known.
// `task_id_constant` false reads E as nqc does a case label, before code
// is generated: __taskid is not a constant yet there.
struct NqcConstant {
  bool constant = false;
  std::optional<std::int16_t> value;
};
using NameBinding = std::function<const ast::Expr*(const ast::Name&)>;
NqcConstant nqc_constant(const ast::Expr& e, const NameBinding& bound, std::optional<std::int16_t> task_id,
                         bool task_id_constant = true);

}  // namespace rcxc::frontend
