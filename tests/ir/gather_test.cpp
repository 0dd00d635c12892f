// ir/gather.cpp: neighbouring constant steps on one variable as one, and
// sums that start with a constant started by their first variable, on
// hand-built IR. The expected constants are worked out by hand.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

using rcx::Op;

// The code of a one-block main after the pass.
std::vector<Instr> gathered(Builder& b, std::vector<Instr> code, bool other_tasks = true) {
  FuncId f = b.function("main");
  b.block(f, std::move(code));
  gather_constant_arithmetic(b.fn(f), b.p.vars, other_tasks);
  return b.at(f, 0).instrs;
}

void expect_step(const Instr& in, Op op, VarId v, Operand x) {
  EXPECT_EQ(in.op, op);
  EXPECT_EQ(in.args[0], V(v));
  EXPECT_EQ(in.args[1], x);
}

}  // namespace

TEST(Gather, AddsAndSubtractsBecomeTheirSum) {
  Builder b;
  VarId g = b.global("g");
  // g - 100 - 10; g + 3 - 1; g + 5 - 5 (nothing); 32767 + 1 wraps.
  auto code = gathered(b, {sub(g, I(100)), sub(g, I(10)), sound(1), add(g, I(3)), sub(g, I(1)), sound(2),
                           add(g, I(5)), sub(g, I(5)), sound(3), add(g, I(32767)), add(g, I(1))});
  ASSERT_EQ(code.size(), 6u);
  expect_step(code[0], Op::SubtractFromVariable, g, I(110));
  expect_step(code[2], Op::AddToVariable, g, I(2));
  EXPECT_EQ(code[3].op, Op::PlaySound);
  EXPECT_EQ(code[4].op, Op::PlaySound);
  expect_step(code[5], Op::AddToVariable, g, I(-32768));
}

TEST(Gather, ProductsAndBitsAndDivisionsByPositiveConstants) {
  Builder b;
  VarId g = b.global("g");
  // * 2 * 5; * 256 * 256 wraps to * 0; * -1 * -1 is nothing; & 255 & 15;
  // | 1 | 2; / 2 / 5.
  auto code = gathered(b, {mul(g, I(2)), mul(g, I(5)), sound(1), mul(g, I(256)), mul(g, I(256)), sound(2),
                           mul(g, I(-1)), mul(g, I(-1)), sound(3), band(g, I(255)), band(g, I(15)), sound(4),
                           bor(g, I(1)), bor(g, I(2)), sound(5), div(g, I(2)), div(g, I(5))});
  ASSERT_EQ(code.size(), 10u);
  expect_step(code[0], Op::MultiplyVariable, g, I(10));
  expect_step(code[2], Op::MultiplyVariable, g, I(0));
  EXPECT_EQ(code[4].op, Op::PlaySound);
  expect_step(code[5], Op::AndVariable, g, I(15));
  expect_step(code[7], Op::OrVariable, g, I(3));
  expect_step(code[9], Op::DivideVariable, g, I(10));
}

TEST(Gather, WhatNoOneStepDoesStaysTwo) {
  Builder b;
  VarId g = b.global("g"), h = b.global("h");
  // Division by a negative constant (-32768 / -1 wraps), divisors whose
  // product leaves 16 bits, a division by zero (the firmware leaves the
  // variable), two variables, two kinds of step, a variable operand, a
  // wait between.
  std::vector<Instr> code = {div(g, I(-2)), div(g, I(3)),   sound(1), div(g, I(200)), div(g, I(200)),
                             sound(2),      div(g, I(0)),   div(g, I(4)), sound(3),   add(g, I(1)),
                             add(h, I(1)),  sound(4),       add(g, I(1)), mul(g, I(2)), sound(5),
                             add(g, V(h)),  add(g, I(1)),   sound(6),     add(g, I(1)), wait(I(5)),
                             add(g, I(1))};
  auto before = code.size();
  EXPECT_EQ(gathered(b, code).size(), before);
}

TEST(Gather, InstructionsWrittenAsAsmStay) {
  Builder b;
  VarId g = b.global("g");
  Instr raw = add(g, I(1));
  raw.raw = true;
  EXPECT_EQ(gathered(b, {raw, add(g, I(1))}).size(), 2u);
}

TEST(Gather, ASumStartedByAConstantStartsWithItsFirstVariable) {
  Builder b;
  VarId g = b.global("g"), h = b.global("h");
  VarId t = b.temp();
  // t = 2 + g + 5 - h  ->  t = g; t -= h; t += 7
  auto code = gathered(b, {set(t, I(2)), add(t, V(g)), add(t, I(5)), sub(t, V(h))});
  ASSERT_EQ(code.size(), 3u);
  expect_step(code[0], Op::SetVariable, t, V(g));
  expect_step(code[1], Op::SubtractFromVariable, t, V(h));
  expect_step(code[2], Op::AddToVariable, t, I(7));
}

TEST(Gather, ConstantsThatCancelLeaveOnlyTheVariables) {
  Builder b;
  VarId g = b.global("g");
  VarId u = b.local("u");
  // u = 0 + g; u = 3 + g - 3
  auto code = gathered(b, {set(u, I(0)), add(u, V(g)), sound(1), set(u, I(3)), add(u, V(g)), sub(u, I(3))});
  ASSERT_EQ(code.size(), 3u);
  expect_step(code[0], Op::SetVariable, u, V(g));
  expect_step(code[2], Op::SetVariable, u, V(g));
}

TEST(Gather, ASumKeepsItsOrderWhereItSavesNothingOrCannot) {
  Builder b;
  VarId g = b.global("g"), h = b.global("h");
  VarId t = b.temp();
  std::vector<Instr> code = {
      set(t, I(2)), add(t, V(g)), sound(1),                 // nothing to gather
      set(t, I(2)), sub(t, V(g)), add(t, I(5)), sound(2),   // the first variable is subtracted
      set(t, I(2)), add(t, V(t)), add(t, I(5)), sound(3),   // t + t reads t itself
      set(h, I(2)), add(h, V(g)), add(h, I(5))};            // a global another task may read
  auto code_after = gathered(b, code);
  EXPECT_EQ(code_after.size(), code.size());
}

TEST(Gather, AGlobalStartsWithItsFirstVariableWhereNoOtherTaskRuns) {
  Builder b;
  VarId g = b.global("g"), h = b.global("h");
  auto code = gathered(b, {set(h, I(2)), add(h, V(g)), add(h, I(5))}, false);
  ASSERT_EQ(code.size(), 2u);
  expect_step(code[0], Op::SetVariable, h, V(g));
  expect_step(code[1], Op::AddToVariable, h, I(7));
}

TEST(Gather, APairThatLeavesTheVariableAsItWasGoes) {
  Builder b;
  VarId g = b.global("g");
  // / 1 / 1, & 0x0f0f & 0xf0f0 is & 0 (stays: it sets 0), | 0 | 0.
  auto code = gathered(b, {div(g, I(1)), div(g, I(1)), sound(1), band(g, I(0x0f0f)), band(g, I(0xf0f0 - 65536)),
                           sound(2), bor(g, I(0)), bor(g, I(0))});
  ASSERT_EQ(code.size(), 3u);
  EXPECT_EQ(code[0].op, Op::PlaySound);
  expect_step(code[1], Op::AndVariable, g, I(0));
  EXPECT_EQ(code[2].op, Op::PlaySound);
}
