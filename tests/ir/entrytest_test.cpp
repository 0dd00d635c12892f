// Loops entered past a test the way in decides (ir/entrytest.cpp).
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

// `entry` then a rotated loop: block 0 runs `entry` and jumps to the test
// (block 2), block 1 is the body (i += 1), block 2 tests i < 10 and goes
// back to the body, block 3 follows the loop. Returns where block 0 jumps.
BlockId entered_at(Builder& b, VarId i, std::vector<Instr> entry, Operand limit = Operand::imm(10)) {
  FuncId f = b.function("main");
  b.block(f, std::move(entry), Jump{2});
  b.block(f, {add(i, I(1))}, Jump{2});
  b.block(f, {}, Branch{Cmp::LT, V(i), limit, 1, 3});
  b.block(f, {sound(1)});
  enter_past_known_tests(b.fn(f), b.p.vars);
  return std::get<Jump>(b.at(f, 0).term).target;
}

// Where the loop is entered when the way in sets `i`, of `kind`, to
// `start`.
BlockId entered_from(VarKind kind, int start) {
  Builder b;
  VarId i = kind == VarKind::Global ? b.global("i") : b.local("i");
  return entered_at(b, i, {set(i, I(start))});
}

}  // namespace

TEST(EntryTest, ALocalSetToAConstantEntersTheBody) {
  // int i = 0; while (i < 10) i++;
  EXPECT_EQ(entered_from(VarKind::Local, 0), 1);
}

TEST(EntryTest, ATestThatFailsOnTheWayInSkipsTheLoop) {
  // int i = 12; while (i < 10) i++; PlaySound(1): the loop goes.
  Builder b;
  VarId i = b.local("i");
  BlockId to = entered_at(b, i, {set(i, I(12))});
  ASSERT_EQ(b.fn(0).blocks.size(), 2u);
  EXPECT_EQ(to, 1);
  EXPECT_TRUE(same_instr(b.at(0, 1).instrs.at(0), sound(1)));
}

TEST(EntryTest, AGlobalKeepsTheTest) {
  // Another task, or a PC, may write it between the set and the test.
  EXPECT_EQ(entered_from(VarKind::Global, 0), 2);
}

TEST(EntryTest, AChangeAfterTheConstantKeepsTheTest) {
  Builder b;
  VarId i = b.local("i"), n = b.local("n");
  EXPECT_EQ(entered_at(b, i, {set(i, I(0)), add(i, V(n))}), 2);
  Builder c;
  VarId j = c.local("j");
  EXPECT_EQ(entered_at(c, j, {set(j, I(0)), op(rcx::Op::SetVariable, {V(j), Operand::src(static_cast<int>(rcx::Source::Random), 5)})}),
            2);
}

TEST(EntryTest, ACallOrRawAsmAfterTheConstantKeepsTheTest) {
  Builder b;
  VarId i = b.local("i");
  FuncId s = b.function("s", FuncKind::Sub);
  b.block(s, {set(i, I(20))});
  EXPECT_EQ(entered_at(b, i, {set(i, I(0)), call(s)}), 2);
  Builder c;
  VarId j = c.local("j");
  EXPECT_EQ(entered_at(c, j, {set(j, I(0)), Instr{rcx::Op::PlaySound, {I(0x51), I(1)}, true}}), 2);
}

TEST(EntryTest, AnUnknownLimitKeepsTheTest) {
  Builder b;
  VarId i = b.local("i"), n = b.local("n");
  EXPECT_EQ(entered_at(b, i, {set(i, I(0))}, V(n)), 2);
  Builder c;
  VarId j = c.local("j");
  EXPECT_EQ(entered_at(c, j, {set(j, I(0))}, Operand::src(static_cast<int>(rcx::Source::SensorValue), 0)), 2);
}

TEST(EntryTest, SaysWhetherItDroppedALoop) {
  // The pipeline removes dead stores again when a loop went: the set that
  // made the test fail may have had no other reader.
  for (auto [start, dropped] : {std::pair{12, true}, std::pair{0, false}}) {
    Builder b;
    VarId i = b.local("i");
    FuncId f = b.function("main");
    b.block(f, {set(i, I(start))}, Jump{2});
    b.block(f, {add(i, I(1))}, Jump{2});
    b.block(f, {}, Branch{Cmp::LT, V(i), I(10), 1, 3});
    b.block(f, {sound(1)});
    EXPECT_EQ(enter_past_known_tests(b.fn(f), b.p.vars), dropped) << "i starts at " << start;
  }
}
