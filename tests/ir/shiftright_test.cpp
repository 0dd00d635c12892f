// ir/shiftright.cpp: right shifts as lowered (a test of the sign and two
// sides) become straight code, on hand-built IR.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

using rcx::Op;

// d >>= n as the lowering leaves it: entry tests d < 0; block 1 the
// negative side, block 2 the other, block 3 the join.
struct Lowered {
  Builder b;
  FuncId f = 0;
  VarId d = 0;
};

Lowered lowered_shift(int negative_divisor, int other_divisor, int bit) {
  Lowered l;
  l.d = l.b.global("d");
  l.f = l.b.function("main");
  l.b.block(l.f, {set(l.d, I(-5))}, Branch{Cmp::LT, V(l.d), I(0), 1, 2});
  l.b.block(l.f, {band(l.d, I(0x7fff)), div(l.d, I(negative_divisor)), bor(l.d, I(bit))}, Jump{3});
  l.b.block(l.f, {div(l.d, I(other_divisor))}, Jump{3});
  l.b.block(l.f, {sound(1)});
  return l;
}

}  // namespace

TEST(ShiftRightPass, AConstantShiftBecomesAndDivideAnd) {
  Lowered l = lowered_shift(8, 8, 4096);  // d >>= 3
  shift_right_without_branches(l.b.fn(l.f), l.b.p.vars, false, true);
  const Block& entry = l.b.at(l.f, 0);
  ASSERT_EQ(entry.instrs.size(), 4u);
  EXPECT_EQ(entry.instrs[1].op, Op::AndVariable);
  EXPECT_EQ(entry.instrs[1].args[1], I(-8));
  EXPECT_EQ(entry.instrs[2].op, Op::DivideVariable);
  EXPECT_EQ(entry.instrs[2].args[1], I(8));
  EXPECT_EQ(entry.instrs[3].op, Op::AndVariable);
  EXPECT_EQ(entry.instrs[3].args[1], I(8191));
  ASSERT_TRUE(std::holds_alternative<Jump>(entry.term));
  EXPECT_EQ(std::get<Jump>(entry.term).target, 3);
}

TEST(ShiftRightPass, OnlyAtOsAShiftOfFewerThanFifteen) {
  // A non-negative d runs the test and one divide; the straight code runs
  // three instructions.
  Lowered l = lowered_shift(8, 8, 4096);
  shift_right_without_branches(l.b.fn(l.f), l.b.p.vars, false, false);
  EXPECT_TRUE(std::holds_alternative<Branch>(l.b.at(l.f, 0).term));
  EXPECT_EQ(l.b.at(l.f, 0).instrs.size(), 1u);
}

TEST(ShiftRightPass, SidesThatAreNoShiftStay) {
  for (auto [neg, other, bit] : {std::tuple{8, 4, 4096}, std::tuple{8, 8, 2048}, std::tuple{6, 6, 4096}}) {
    Lowered l = lowered_shift(neg, other, bit);
    shift_right_without_branches(l.b.fn(l.f), l.b.p.vars, false, true);
    EXPECT_TRUE(std::holds_alternative<Branch>(l.b.at(l.f, 0).term)) << neg << " " << other << " " << bit;
  }
}

TEST(ShiftRightPass, TheSignAsZeroOrOneIsAndAndDivide) {
  // d = (d < 0), as d >>= 15 lowers: both sides set a constant.
  Builder b;
  VarId d = b.local("d");
  FuncId f = b.function("main");
  b.block(f, {set(d, I(-5))}, Branch{Cmp::GE, I(0), V(d), 1, 2});  // 0 >= d: not the sign test
  b.block(f, {set(d, I(1))}, Jump{3});
  b.block(f, {set(d, I(0))}, Jump{3});
  b.block(f, {sound(1)});
  shift_right_without_branches(b.fn(f), b.p.vars, false, false);
  EXPECT_TRUE(std::holds_alternative<Branch>(b.at(f, 0).term));
  std::get<Branch>(b.at(f, 0).term) = Branch{Cmp::LE, I(0), V(d), 2, 1};  // 0 <= d: d >= 0
  shift_right_without_branches(b.fn(f), b.p.vars, false, false);
  const Block& entry = b.at(f, 0);
  ASSERT_EQ(entry.instrs.size(), 3u);
  EXPECT_EQ(entry.instrs[1].op, Op::AndVariable);
  EXPECT_EQ(entry.instrs[1].args[1], I(-32768));
  EXPECT_EQ(entry.instrs[2].op, Op::DivideVariable);
  EXPECT_EQ(entry.instrs[2].args[1], I(-32768));
  EXPECT_EQ(std::get<Jump>(entry.term).target, 3);
}

TEST(ShiftRightPass, AGlobalAnotherTaskMayReadKeepsTheTest) {
  // d &= -32768 would show another task -32768 for a negative d, a value
  // neither the source nor nqc's code gives it; a local still goes straight.
  for (bool global : {true, false}) {
    Builder b;
    VarId d = global ? b.global("d") : b.local("d");
    FuncId f = b.function("main");
    b.block(f, {set(d, I(-5))}, Branch{Cmp::LT, V(d), I(0), 1, 2});
    b.block(f, {set(d, I(1))}, Jump{3});
    b.block(f, {set(d, I(0))}, Jump{3});
    b.block(f, {sound(1)});
    shift_right_without_branches(b.fn(f), b.p.vars, true, true);
    EXPECT_EQ(std::holds_alternative<Branch>(b.at(f, 0).term), global);
  }
  Lowered l = lowered_shift(8, 8, 4096);  // d >>= 3 at -Os, d a global
  shift_right_without_branches(l.b.fn(l.f), l.b.p.vars, true, true);
  EXPECT_TRUE(std::holds_alternative<Branch>(l.b.at(l.f, 0).term));
  shift_right_without_branches(l.b.fn(l.f), l.b.p.vars, false, true);  // one task: nobody to see
  EXPECT_TRUE(std::holds_alternative<Jump>(l.b.at(l.f, 0).term));
}
