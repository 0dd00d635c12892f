// Constant arithmetic of the target: 16-bit two's complement with wrap-around,
// shared by semantic analysis and frontend::fold_constant.
#pragma once

#include <cstdint>
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

}  // namespace rcxc::frontend
