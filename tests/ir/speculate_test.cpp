// If/else speculation (ir/speculate.cpp): which assignments move before
// the test, and which must stay on their side.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

// if (x > 2) t = then_value; else t = else_value; sound(1):
// 0 tests, 1 is the then side, 2 the else side, 3 the join.
Builder if_else(VarId (*make)(Builder&), Operand then_value, Operand else_value, VarId* t_out = nullptr,
                VarId* x_out = nullptr) {
  Builder b;
  VarId x = b.global("x");
  VarId t = make(b);
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::GT, V(x), I(2), 1, 2});
  b.block(f, {set(t, then_value)}, Jump{3});
  b.block(f, {set(t, else_value)}, Jump{3});
  b.block(f, {sound(1)});
  if (t_out) *t_out = t;
  if (x_out) *x_out = x;
  return b;
}

VarId a_local(Builder& b) { return b.local("t"); }
VarId a_global(Builder& b) { return b.global("t"); }

bool speculated(Builder& b) {
  Function& f = b.fn(0);
  speculate_assignments(f, b.p.vars);
  const auto& br = std::get<Branch>(f.blocks[0].term);
  return !f.blocks[0].instrs.empty() && (br.then == 3 || br.otherwise == 3);
}

}  // namespace

TEST(Speculate, TheElseValueIsSetBeforeTheTest) {
  VarId t = -1;
  Builder b = if_else(a_local, I(7), I(9), &t);
  ASSERT_TRUE(speculated(b));
  const Function& f = b.fn(0);
  // t = 9 first; the test goes to the join when x > 2 fails.
  ASSERT_EQ(f.blocks[0].instrs.size(), 1u);
  EXPECT_EQ(f.blocks[0].instrs[0].args[1], I(9));
  const auto& br = std::get<Branch>(f.blocks[0].term);
  EXPECT_EQ(br.then, 1);
  EXPECT_EQ(br.otherwise, 3);
}

TEST(Speculate, AGlobalStaysOnItsSide) {
  // Another task could read the global between the two sets.
  Builder b = if_else(a_global, I(7), I(9));
  EXPECT_FALSE(speculated(b));
}

TEST(Speculate, ATestOfTheVariableItselfStays) {
  // if (t > 2) t = 7; else t = 9: setting t first would change the test.
  Builder b;
  VarId t = b.local("t");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::GT, V(t), I(2), 1, 2});
  b.block(f, {set(t, I(7))}, Jump{3});
  b.block(f, {set(t, I(9))}, Jump{3});
  b.block(f, {sound(1)});
  EXPECT_FALSE(speculated(b));
}

TEST(Speculate, ARandomValueIsNotDrawnOnBothPaths) {
  // Each read of the random source draws a number.
  Builder b = if_else(a_local, I(7), Operand::src(static_cast<int>(rcx::Source::Random), 9));
  Builder c = if_else(a_local, Operand::src(static_cast<int>(rcx::Source::Random), 9), I(7));
  EXPECT_FALSE(speculated(b));
  EXPECT_FALSE(speculated(c));
}

TEST(Speculate, ASideOthersJumpToStays) {
  // Blocks 1 and 2 are also where block 4 goes: each must still set t for
  // that path, so neither set can move before the first test.
  VarId t = -1, x = -1;
  Builder b = if_else(a_local, I(7), I(9), &t, &x);
  b.fn(0).blocks[3].term = Branch{Cmp::EQ, V(x), I(0), 4, 5};
  b.block(0, {}, Branch{Cmp::EQ, V(x), I(1), 1, 2});
  b.block(0, {sound(2)});
  EXPECT_FALSE(speculated(b));
}
