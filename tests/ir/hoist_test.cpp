// Hoisting common heads (ir/hoist.cpp): what both sides of a test begin
// with runs once before the test, and what could change the test stays.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

const Operand kMotorStateA = Operand::src(static_cast<int>(rcx::Source::MotorState), 0);
const Operand kRandom = Operand::src(static_cast<int>(rcx::Source::Random), 9);

// if (a cmp b) { then_code } else { else_code } sound(9):
// 0 tests, 1 is the then side, 2 the else side, 3 the join. Variable 0 is
// a global `x`.
Builder if_else(Branch test, std::vector<Instr> then_code, std::vector<Instr> else_code) {
  Builder b;
  b.global("x");
  FuncId f = b.function("main");
  test.then = 1;
  test.otherwise = 2;
  b.block(f, {}, test);
  b.block(f, std::move(then_code), Jump{3});
  b.block(f, std::move(else_code), Jump{3});
  b.block(f, {sound(9)});
  return b;
}

Branch test_of(Operand a, Operand b) { return Branch{Cmp::EQ, a, b, 0, 0}; }

// if (x == 1) { then_code } else { else_code } sound(9), with x main's
// local (variable 0) and y a global (variable 1).
constexpr VarId kLocalX = 0, kGlobalY = 1;
Builder if_local_else(std::vector<Instr> then_code, std::vector<Instr> else_code) {
  Builder b;
  b.local("x");
  b.global("y");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, V(kLocalX), I(1), 1, 2});
  b.block(f, std::move(then_code), Jump{3});
  b.block(f, std::move(else_code), Jump{3});
  b.block(f, {sound(9)});
  return b;
}

std::size_t hoisted(Builder& b) {
  Log log;
  hoist_common_heads(b.p, log);
  EXPECT_EQ(log.size(), b.fn(0).blocks[0].instrs.size());
  return b.fn(0).blocks[0].instrs.size();
}

}  // namespace

TEST(Hoist, ACommonMotorCommandRunsOnceBeforeTheTest) {
  // if (d == 1) { SetPower(AC, 3); Rev(A); } else { SetPower(AC, 3); Rev(C); }
  Builder b = if_else(test_of(V(0), I(1)), {pwr(5, 3), dir(0x01)}, {pwr(5, 3), dir(0x04)});
  ASSERT_EQ(hoisted(b), 1u);
  const Function& f = b.fn(0);
  EXPECT_TRUE(same_instr(f.blocks[0].instrs[0], pwr(5, 3)));
  ASSERT_EQ(f.blocks[1].instrs.size(), 1u);
  EXPECT_TRUE(same_instr(f.blocks[1].instrs[0], dir(0x01)));
  ASSERT_EQ(f.blocks[2].instrs.size(), 1u);
  EXPECT_TRUE(same_instr(f.blocks[2].instrs[0], dir(0x04)));
}

TEST(Hoist, EveryCommonInstructionMovesUntilTheSidesDiffer) {
  Builder b = if_else(test_of(V(0), I(1)), {sound(1), out(0x85), sound(2)}, {sound(1), out(0x85), sound(3)});
  EXPECT_EQ(hoisted(b), 2u);
  EXPECT_EQ(b.fn(0).blocks[1].instrs.size(), 1u);
  EXPECT_EQ(b.fn(0).blocks[2].instrs.size(), 1u);
}

TEST(Hoist, SidesThatDifferFromTheStartStay) {
  Builder b = if_else(test_of(V(0), I(1)), {sound(1), sound(2)}, {sound(2), sound(1)});
  EXPECT_EQ(hoisted(b), 0u);
}

TEST(Hoist, AnAssignmentToWhatTheTestReadsStays) {
  // if (x == 1) { x = 5; ... } else { x = 5; ... }: setting x first would
  // change the test.
  Builder b = if_local_else({set(kLocalX, I(5)), sound(1)}, {set(kLocalX, I(5)), sound(2)});
  EXPECT_EQ(hoisted(b), 0u);
}

TEST(Hoist, ArithmeticIntoAnotherVariableMoves) {
  Builder b = if_local_else({add(kGlobalY, I(2)), sound(1)}, {add(kGlobalY, I(2)), sound(2)});
  ASSERT_EQ(hoisted(b), 1u);
  EXPECT_TRUE(same_instr(b.fn(0).blocks[0].instrs[0], add(kGlobalY, I(2))));
}

TEST(Hoist, AMotorCommandStaysWhenTheTestReadsAnOutput) {
  Builder b = if_else(test_of(kMotorStateA, I(0)), {out(0x81), sound(1)}, {out(0x81), sound(2)});
  EXPECT_EQ(hoisted(b), 0u);
}

TEST(Hoist, WaitsCallsAndOtherCommandsStay) {
  // A wait would delay the test's reading of the sensor; commands outside
  // the list (clearing the message here) stay whatever the test reads.
  const Operand sensor = Operand::src(static_cast<int>(rcx::Source::SensorValue), 0);
  Builder w = if_else(test_of(sensor, I(1)), {wait(I(10)), sound(1)}, {wait(I(10)), sound(2)});
  EXPECT_EQ(hoisted(w), 0u);
  Builder t = if_else(test_of(sensor, I(1)), {filler(), sound(1)}, {filler(), sound(2)});
  EXPECT_EQ(hoisted(t), 0u);
}

TEST(Hoist, TwoRandomDrawsKeepTheirOrder) {
  // The test draws a number; a side's draw moved before it would swap them.
  Builder b;
  VarId y = b.local("y");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, kRandom, I(1), 1, 2});
  b.block(f, {set(y, kRandom), sound(1)}, Jump{3});
  b.block(f, {set(y, kRandom), sound(2)}, Jump{3});
  b.block(f, {sound(9)});
  EXPECT_EQ(hoisted(b), 0u);
}

TEST(Hoist, ASideEnteredFromElsewhereStays) {
  // Block 2 is also the target of block 3's jump: code moved out of it
  // would no longer run on that way in.
  Builder b;
  VarId x = b.local("x");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, V(x), I(1), 1, 2});
  b.block(f, {sound(1), sound(2)}, Jump{3});
  b.block(f, {sound(1), sound(3)}, Jump{3});
  b.block(f, {sound(9)}, Branch{Cmp::EQ, V(x), I(2), 2, 4});
  b.block(f, {});
  EXPECT_EQ(hoisted(b), 0u);
}

TEST(Hoist, AnAssignmentStaysWhenTheTestReadsAVariableByNumber) {
  // if (@0 == 1) { x = 5; ... } else { x = 5; ... }: `@0` is slot 0, the
  // global x's (globals keep nqc's slots), so setting x first would change
  // the test.
  const Operand slot0 = Operand::src(static_cast<int>(rcx::Source::Variable), 0);
  Builder b = if_else(test_of(slot0, I(1)), {set(0, I(5)), sound(1)}, {set(0, I(5)), sound(2)});
  EXPECT_EQ(hoisted(b), 0u);
  // A motor command or sound changes no variable: it still moves.
  Builder m = if_else(test_of(slot0, I(1)), {out(0x81), sound(1)}, {out(0x81), sound(2)});
  EXPECT_EQ(hoisted(m), 1u);
}

namespace {

// if_else's program with a second task, which could copy one global into
// another or poll an output while main runs.
Builder with_other_task(Builder b) {
  FuncId other = b.function("other");
  b.block(other, {sound(7)});
  return b;
}

}  // namespace

TEST(Hoist, WithOtherTasksWhatTheyCanSeeStaysAfterATestOfWhatTheyCanChange) {
  // task copier() { while (true) x = y; } and main's
  // if (x == 1) { y = 1; ... } else { y = 1; ... }: y set before the
  // test, the copier could make x 1 in the instruction between.
  auto globals = [](std::vector<Instr> then_code, std::vector<Instr> else_code) {
    Builder b = if_else(test_of(V(0), I(1)), std::move(then_code), std::move(else_code));
    b.global("y");  // variable 1
    return b;
  };
  Builder assigned = with_other_task(globals({set(1, I(1)), sound(1)}, {set(1, I(1)), sound(2)}));
  EXPECT_EQ(hoisted(assigned), 0u);
  // A task polling output A could set x when it sees A on.
  Builder motor = with_other_task(globals({out(0x81), sound(1)}, {out(0x81), sound(2)}));
  EXPECT_EQ(hoisted(motor), 0u);
  // A sensor, a timer or the message could be changed in answer too.
  const Operand timer = Operand::src(static_cast<int>(rcx::Source::Timer), 0);
  Builder timed = with_other_task(if_else(test_of(timer, I(1)), {out(0x81), sound(1)}, {out(0x81), sound(2)}));
  EXPECT_EQ(hoisted(timed), 0u);
  // A sound no task can see: it moves.
  Builder sounds = with_other_task(globals({sound(4), sound(1)}, {sound(4), sound(2)}));
  EXPECT_EQ(hoisted(sounds), 1u);
  // Alone, main moves both: nothing can answer between.
  Builder alone = globals({set(1, I(1)), out(0x81), sound(1)}, {set(1, I(1)), out(0x81), sound(2)});
  EXPECT_EQ(hoisted(alone), 2u);
}

TEST(Hoist, WithOtherTasksATestOfMainsOwnVariableStillTakesTheCommand) {
  // No other task writes a local: nothing can answer before the test.
  Builder b = with_other_task(
      if_local_else({set(kGlobalY, I(2)), out(0x81), sound(1)}, {set(kGlobalY, I(2)), out(0x81), sound(2)}));
  EXPECT_EQ(hoisted(b), 2u);
}
