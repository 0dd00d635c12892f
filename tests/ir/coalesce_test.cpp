// ir/coalesce.cpp: computing into the assigned variable instead of into a
// temporary copied there, on hand-built IR.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

using rcx::Op;

TEST(Coalesce, ACommutingOperationOnTheTargetIsDoneInPlace) {
  // b = a * b lowered as t = a; t *= b; b = t.
  Builder b;
  VarId a = b.global("a"), g = b.global("b");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, V(a)), mul(t, V(g)), set(g, V(t))});
  compute_into_targets(b.p);
  ASSERT_EQ(b.at(f, 0).instrs.size(), 1u);
  EXPECT_EQ(b.at(f, 0).instrs[0].op, Op::MultiplyVariable);
  EXPECT_EQ(b.at(f, 0).instrs[0].args[0], V(g));
  EXPECT_EQ(b.at(f, 0).instrs[0].args[1], V(a));
}

TEST(Coalesce, TheEndOfARemainderOfTheTargetIsOneSubtraction) {
  // g = g % 4: t = g; t /= 4; t *= 4; t -= g; t *= -1; g = t.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, V(g)), div(t, I(4)), mul(t, I(4)), sub(t, V(g)), mul(t, I(-1)), set(g, V(t))});
  compute_into_targets(b.p);
  const auto& code = b.at(f, 0).instrs;
  ASSERT_EQ(code.size(), 4u);
  EXPECT_EQ(code[3].op, Op::SubtractFromVariable);
  EXPECT_EQ(code[3].args[0], V(g));
  EXPECT_EQ(code[3].args[1], V(t));
}

TEST(Coalesce, AReverseSubtractionIntoAnotherVariableStartsFromItsLeftSide) {
  // h = x - t as t -= x; t *= -1; h = t  ->  h = x; h -= t.
  Builder b;
  VarId x = b.global("x"), h = b.global("h");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, I(9)), div(t, V(x)), sub(t, V(x)), mul(t, I(-1)), set(h, V(t))});
  compute_into_targets(b.p);
  const auto& code = b.at(f, 0).instrs;
  ASSERT_EQ(code.size(), 4u);
  EXPECT_EQ(code[2].op, Op::SetVariable);
  EXPECT_EQ(code[2].args[0], V(h));
  EXPECT_EQ(code[2].args[1], V(x));
  EXPECT_EQ(code[3].op, Op::SubtractFromVariable);
}

TEST(Coalesce, ASubtractionFromAValueNegatesTheTarget) {
  // z = y - z: t = y; t -= z; z = t  ->  z -= y; z *= -1.
  Builder b;
  VarId y = b.global("y"), z = b.global("z");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, V(y)), sub(t, V(z)), set(z, V(t))});
  compute_into_targets(b.p);
  const auto& code = b.at(f, 0).instrs;
  ASSERT_EQ(code.size(), 2u);
  EXPECT_EQ(code[0].op, Op::SubtractFromVariable);
  EXPECT_EQ(code[0].args[0], V(z));
  EXPECT_EQ(code[0].args[1], V(y));
  EXPECT_EQ(code[1].op, Op::MultiplyVariable);
  EXPECT_EQ(code[1].args[1], I(-1));
}

TEST(Coalesce, ATemporaryStillReadIsKept) {
  // t is read after the copy (here by the branch, and in another block):
  // nothing may change.
  Builder b;
  VarId a = b.global("a"), g = b.global("b");
  FuncId f = b.function("main");
  VarId t = b.temp(), u = b.temp();
  b.block(f, {set(t, V(a)), mul(t, V(g)), set(g, V(t))}, Branch{Cmp::EQ, V(t), I(0), 1, 2});
  b.block(f, {set(u, V(a)), add(u, V(g)), set(g, V(u))}, Jump{2});
  b.block(f, {set(a, V(u))});
  compute_into_targets(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 3u);
  EXPECT_EQ(b.at(f, 1).instrs.size(), 3u);
}

TEST(Coalesce, AGlobalIsNeverTheTemporary) {
  // Another task may read g: its value is no temporary.
  Builder b;
  VarId a = b.global("a"), g = b.global("g"), h = b.global("h");
  FuncId f = b.function("main");
  b.block(f, {set(g, V(a)), mul(g, V(h)), set(h, V(g))});
  compute_into_targets(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 3u);
}

TEST(Waits, ConsecutiveConstantWaitsBecomeOne) {
  // Wait(6); Wait(100); then a wait of a variable, which stays apart.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {wait(I(6)), wait(I(100)), sound(1), wait(I(2)), wait(I(2)), wait(V(g))});
  merge_consecutive_waits(b.fn(f));
  const auto& code = b.at(f, 0).instrs;
  ASSERT_EQ(code.size(), 4u);
  EXPECT_EQ(code[0].args[0], I(106));
  EXPECT_EQ(code[2].args[0], I(4));
  EXPECT_EQ(code[3].args[0], V(g));
}

TEST(Waits, WaitsInTwoBlocksStayApart) {
  // The second wait is a branch target: a path reaches it without the first.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {wait(I(5))}, Branch{Cmp::EQ, V(g), I(0), 1, 1});
  b.block(f, {wait(I(7))});
  merge_consecutive_waits(b.fn(f));
  EXPECT_EQ(b.at(f, 0).instrs.size(), 1u);
  EXPECT_EQ(b.at(f, 1).instrs.size(), 1u);
}

TEST(NegatedTest, AnEqualityTestNeedsNoNegation) {
  // t = -t; if (t != 3) ...  ->  if (t != -3) ...
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, V(g)), mul(t, I(-1))}, Branch{Cmp::NE, V(t), I(3), 1, 2});
  b.block(f, {sound(1)});
  b.block(f, {sound(2)});
  test_before_one_to_one_arithmetic(b.p);
  // The copy goes too: g itself is tested.
  ASSERT_EQ(b.at(f, 0).instrs.size(), 0u);
  const auto& br = std::get<Branch>(b.at(f, 0).term);
  EXPECT_EQ(br.a, V(g));
  EXPECT_EQ(br.b, I(-3));
}

TEST(NegatedTest, EqualityThroughAdditionsOddProductsAndReverseSubtraction) {
  // (g * 3 + 5 == 2), (10 - g != 4), each value read nowhere after.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp(), u = b.temp();
  b.block(f, {set(t, V(g)), mul(t, I(3)), add(t, I(5))}, Branch{Cmp::EQ, I(2), V(t), 1, 1});
  b.block(f, {set(u, I(10)), sub(u, V(g))}, Branch{Cmp::NE, V(u), I(4), 2, 2});
  b.block(f, {sound(1)});
  test_before_one_to_one_arithmetic(b.p);
  ASSERT_EQ(b.at(f, 0).instrs.size(), 0u);
  const auto& first = std::get<Branch>(b.at(f, 0).term);
  EXPECT_EQ(first.a, V(g));
  // g * 3 == -3 (mod 2^16): g == -1, since 3 * -1 == -3.
  EXPECT_EQ(first.b, I(-1));
  EXPECT_EQ(first.cmp, Cmp::EQ);
  ASSERT_EQ(b.at(f, 1).instrs.size(), 0u);
  const auto& second = std::get<Branch>(b.at(f, 1).term);
  EXPECT_EQ(second.a, V(g));
  EXPECT_EQ(second.b, I(6));
}

TEST(NegatedTest, AnOrderedTestGoesThroughAComplementOnly) {
  // ~g <= 5 is g >= -6; g + 1 <= 0 stays (32767 + 1 wraps); an even
  // product stays for equality too (g * 2 == 0 also at g == -32768).
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp(), u = b.temp(), w = b.temp();
  b.block(f, {set(t, I(-1)), sub(t, V(g))}, Branch{Cmp::LE, V(t), I(5), 1, 1});
  b.block(f, {set(u, V(g)), add(u, I(1))}, Branch{Cmp::LE, V(u), I(0), 2, 2});
  b.block(f, {set(w, V(g)), mul(w, I(2))}, Branch{Cmp::EQ, V(w), I(0), 3, 3});
  b.block(f, {sound(1)});
  test_before_one_to_one_arithmetic(b.p);
  ASSERT_EQ(b.at(f, 0).instrs.size(), 0u);
  const auto& br = std::get<Branch>(b.at(f, 0).term);
  EXPECT_EQ(br.a, V(g));
  EXPECT_EQ(br.b, I(-6));
  EXPECT_EQ(br.cmp, Cmp::GE);
  EXPECT_EQ(b.at(f, 1).instrs.size(), 2u);
  EXPECT_EQ(b.at(f, 2).instrs.size(), 2u);
}

TEST(NegatedTest, OrderedTestsAndValuesReadLaterKeepTheNegation) {
  // -(-32768) < 0 holds where -32768 > 0 does not: an ordered test keeps
  // its negation; so does a value read after the test.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp(), u = b.temp();
  b.block(f, {set(t, V(g)), mul(t, I(-1))}, Branch{Cmp::LT, V(t), I(0), 1, 1});
  b.block(f, {set(u, V(g)), mul(u, I(-1))}, Branch{Cmp::EQ, I(0), V(u), 2, 2});
  b.block(f, {set(g, V(u))});
  test_before_one_to_one_arithmetic(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 2u);
  EXPECT_EQ(b.at(f, 1).instrs.size(), 2u);
}

TEST(NegatedTest, ALocalCopiedFromASensorIsTheSensorTested) {
  // v = SENSOR_2; if (v > 50): one read, the test's, where the copy's was;
  // a random number or a value read after the test keeps its copy.
  Builder b;
  FuncId f = b.function("main");
  VarId v = b.local("v"), r = b.local("r"), w = b.local("w");
  Operand sensor = Operand::src(static_cast<int>(rcx::Source::SensorValue), 1);
  b.block(f, {set(v, sensor)}, Branch{Cmp::GT, V(v), I(50), 1, 1});
  b.block(f, {set(r, Operand::src(static_cast<int>(rcx::Source::Random), 5))}, Branch{Cmp::EQ, V(r), I(3), 2, 2});
  b.block(f, {set(w, sensor)}, Branch{Cmp::EQ, V(w), I(1), 3, 3});
  b.block(f, {add(w, I(1)), sound(1)}, Jump{0});
  test_before_one_to_one_arithmetic(b.p);
  ASSERT_EQ(b.at(f, 0).instrs.size(), 0u);
  const auto& br = std::get<Branch>(b.at(f, 0).term);
  EXPECT_EQ(br.a, sensor);
  EXPECT_EQ(br.b, I(50));
  EXPECT_EQ(br.cmp, Cmp::GT);
  EXPECT_EQ(b.at(f, 1).instrs.size(), 1u);
  EXPECT_EQ(b.at(f, 2).instrs.size(), 1u);
}

TEST(JoinConstant, ArithmeticAtAJoinMovesIntoTheConstantsReachingIt) {
  // t = 0; if (a < b) t = 1; t *= 3; t -= 1; g = t.
  Builder b;
  VarId a = b.global("a"), g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, I(0))}, Branch{Cmp::LT, V(a), V(g), 1, 2});
  b.block(f, {set(t, I(1))}, Jump{2});
  b.block(f, {mul(t, I(3)), sub(t, I(1)), set(g, V(t))});
  push_constant_ops_into_predecessors(b.fn(f), b.p.vars);
  EXPECT_EQ(b.at(f, 0).instrs[0].args[1], I(-1));
  EXPECT_EQ(b.at(f, 1).instrs[0].args[1], I(2));
  ASSERT_EQ(b.at(f, 2).instrs.size(), 1u);
  EXPECT_EQ(b.at(f, 2).instrs[0].op, Op::SetVariable);
}

TEST(JoinConstant, AGlobalOrAConstantSeenElsewhereStays) {
  // g is global (another task may write it before the join); u's 0 also
  // reaches block 3, which reads it.
  Builder b;
  VarId a = b.global("a"), g = b.global("g");
  FuncId f = b.function("main");
  VarId u = b.temp();
  b.block(f, {set(g, I(0)), set(u, I(0))}, Branch{Cmp::LT, V(a), I(5), 1, 3});
  b.block(f, {set(g, I(1)), set(u, I(1))}, Jump{2});
  b.block(f, {mul(g, I(3)), add(u, I(4)), set(a, V(u))});
  b.block(f, {set(a, V(u))}, Jump{2});
  push_constant_ops_into_predecessors(b.fn(f), b.p.vars);
  EXPECT_EQ(b.at(f, 2).instrs.size(), 3u);
  EXPECT_EQ(b.at(f, 0).instrs[0].args[1], I(0));
  EXPECT_EQ(b.at(f, 0).instrs[1].args[1], I(0));
}

TEST(JoinConstant, AComparisonAddedToAVariableIsAnAdditionOnOneSide) {
  // t = 0; if (a < 5) t = 1; g += t;  ->  if (a < 5) g += 1;
  Builder b;
  VarId a = b.global("a"), g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, I(0))}, Branch{Cmp::LT, V(a), I(5), 1, 2});
  b.block(f, {set(t, I(1))}, Jump{2});
  b.block(f, {add(g, V(t)), sound(1)});
  apply_constants_in_predecessors(b.p);
  ASSERT_EQ(b.at(f, 2).instrs.size(), 1u);  // the sound
  ASSERT_EQ(b.at(f, 1).instrs.size(), 2u);
  EXPECT_EQ(b.at(f, 1).instrs[1].op, Op::AddToVariable);
  EXPECT_EQ(b.at(f, 1).instrs[1].args[0], V(g));
  EXPECT_EQ(b.at(f, 1).instrs[1].args[1], I(1));
  EXPECT_EQ(b.at(f, 0).instrs.size(), 1u);  // t = 0, left to the dead stores
}

TEST(JoinConstant, AProductNeedsEverySideToJumpOrToChangeNothing) {
  // g *= t with t = 0 on the test's side (g = 0 there would also go to
  // block 1): stays. g /= u with 0 or 1 changes nothing either way: goes.
  // w read again after the join: stays.
  Builder b;
  VarId a = b.global("a"), g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp(), u = b.temp(), w = b.temp();
  b.block(f, {set(t, I(0))}, Branch{Cmp::LT, V(a), I(5), 1, 2});
  b.block(f, {set(t, I(1))}, Jump{2});
  b.block(f, {mul(g, V(t)), set(u, I(0))}, Branch{Cmp::LT, V(a), I(7), 3, 4});
  b.block(f, {set(u, I(1))}, Jump{4});
  b.block(f, {div(g, V(u)), set(w, I(0))}, Branch{Cmp::LT, V(a), I(9), 5, 6});
  b.block(f, {set(w, I(1))}, Jump{6});
  b.block(f, {sub(g, V(w)), set(a, V(w))});
  apply_constants_in_predecessors(b.p);
  EXPECT_EQ(b.at(f, 2).instrs.size(), 2u);
  ASSERT_EQ(b.at(f, 4).instrs.size(), 1u);
  EXPECT_EQ(b.at(f, 4).instrs[0].op, Op::SetVariable);
  EXPECT_EQ(b.at(f, 6).instrs.size(), 2u);
}

TEST(NonZero, AComparisonWithZeroIsTheSignOfTheAbsoluteValue) {
  // d = 0; if (v != 0) d = 1;  ->  d = abs(v); d = sign(d);
  Builder b;
  VarId v = b.global("v"), d = b.global("d");
  FuncId f = b.function("main");
  b.block(f, {set(d, I(0))}, Branch{Cmp::EQ, I(0), V(v), 2, 1});
  b.block(f, {set(d, I(1))}, Jump{2});
  b.block(f, {sound(1)});
  compute_nonzero_by_sign(b.fn(f), b.p.vars, false);
  const auto& code = b.at(f, 0).instrs;
  ASSERT_EQ(code.size(), 2u);
  EXPECT_EQ(code[0].op, Op::AbsoluteValue);
  EXPECT_EQ(code[0].args[1], V(v));
  EXPECT_EQ(code[1].op, Op::SignVariable);
  ASSERT_TRUE(std::holds_alternative<Jump>(b.at(f, 0).term));
  EXPECT_EQ(std::get<Jump>(b.at(f, 0).term).target, 2);
}

TEST(NonZero, NotIntoAGlobalAnotherTaskMayRead) {
  // The same shape with other tasks running: d would hold |v| for an
  // instruction, which a task waiting for d > 1 sees. A local is still
  // rewritten.
  Builder b;
  VarId v = b.global("v"), d = b.global("d"), l = b.local("l");
  FuncId f = b.function("main");
  b.block(f, {set(d, I(0))}, Branch{Cmp::EQ, I(0), V(v), 2, 1});
  b.block(f, {set(d, I(1))}, Jump{2});
  b.block(f, {set(l, I(0))}, Branch{Cmp::EQ, I(0), V(v), 4, 3});
  b.block(f, {set(l, I(1))}, Jump{4});
  b.block(f, {sound(1)});
  compute_nonzero_by_sign(b.fn(f), b.p.vars, true);
  EXPECT_TRUE(std::holds_alternative<Branch>(b.at(f, 0).term));
  ASSERT_TRUE(std::holds_alternative<Jump>(b.at(f, 2).term));
  EXPECT_EQ(b.at(f, 2).instrs.back().op, Op::SignVariable);
}

TEST(NonZero, OtherValuesOrOtherSidesStay) {
  // d = 0; if (v == 0) d = 1: (v == 0) is no sign; and a side that does
  // more than set d.
  Builder b;
  VarId v = b.global("v"), d = b.global("d");
  FuncId f = b.function("main");
  b.block(f, {set(d, I(0))}, Branch{Cmp::NE, I(0), V(v), 2, 1});
  b.block(f, {set(d, I(1))}, Jump{2});
  b.block(f, {set(d, I(0))}, Branch{Cmp::EQ, I(0), V(v), 4, 3});
  b.block(f, {set(d, I(1)), sound(2)}, Jump{4});
  b.block(f, {sound(1)});
  compute_nonzero_by_sign(b.fn(f), b.p.vars, false);
  EXPECT_TRUE(std::holds_alternative<Branch>(b.at(f, 0).term));
  EXPECT_TRUE(std::holds_alternative<Branch>(b.at(f, 2).term));
}
