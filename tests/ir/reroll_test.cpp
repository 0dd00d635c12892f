// Loop rerolling on hand-built IR. Sizes: wait 4 bytes, sound 2, set/add
// 5, a near test 7, so a loop costs 17 bytes besides one copy of the group.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

// Four copies of {wait 10*i; sound 1}: 3 x 6 bytes saved against 17.
Builder four_waits_and_sounds() {
  Builder b;
  FuncId t = b.function("main");
  b.block(t, {sound(3), wait(I(10)), sound(1), wait(I(20)), sound(1), wait(I(30)), sound(1), wait(I(40)), sound(1),
              filler()});
  return b;
}

}  // namespace

TEST(Reroll, StepConstantsBecomeALoopOverATemporary) {
  Builder b = four_waits_and_sounds();
  Log log;
  ASSERT_TRUE(reroll_sequences(b.p, log));
  const Function& f = b.p.functions[0];
  ASSERT_EQ(f.blocks.size(), 3u);
  ASSERT_EQ(b.p.vars.size(), 1u);
  VarId t = 0;
  EXPECT_EQ(b.p.vars[0].kind, VarKind::Temp);
  // Before: what preceded the run, then the counter starts at the first value.
  ASSERT_EQ(f.blocks[0].instrs.size(), 2u);
  EXPECT_EQ(f.blocks[0].instrs[0].op, rcx::Op::PlaySound);
  EXPECT_EQ(f.blocks[0].instrs[1].op, rcx::Op::SetVariable);
  EXPECT_EQ(f.blocks[0].instrs[1].args, (std::vector<Operand>{V(t), I(10)}));
  ASSERT_TRUE(std::holds_alternative<Jump>(f.blocks[0].term));
  EXPECT_EQ(std::get<Jump>(f.blocks[0].term).target, 1);
  // The loop: one copy reading the counter, the step, and a test against
  // the value after the last copy (10 + 4 * 10).
  const auto& body = f.blocks[1].instrs;
  ASSERT_EQ(body.size(), 3u);
  EXPECT_EQ(body[0].op, rcx::Op::Wait);
  EXPECT_EQ(body[0].args[0], V(t));
  EXPECT_EQ(body[1].args[0], I(1));
  EXPECT_EQ(body[2].op, rcx::Op::AddToVariable);
  EXPECT_EQ(body[2].args, (std::vector<Operand>{V(t), I(10)}));
  const auto* br = std::get_if<Branch>(&f.blocks[1].term);
  ASSERT_NE(br, nullptr);
  EXPECT_EQ(br->cmp, Cmp::NE);
  EXPECT_EQ(br->a, I(50));
  EXPECT_EQ(br->b, V(t));
  EXPECT_EQ(br->then, 1);
  EXPECT_EQ(br->otherwise, 2);
  // After: the rest and the old terminator.
  ASSERT_EQ(f.blocks[2].instrs.size(), 1u);
  EXPECT_EQ(f.blocks[2].instrs[0].op, rcx::Op::ClearMessage);
  EXPECT_TRUE(std::holds_alternative<Exit>(f.blocks[2].term));
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("4 copies of 2 instructions"), std::string::npos) << log[0];
}

TEST(Reroll, NegativeAndWrappingStepsEndAfterTheLastCopy) {
  Builder b;
  FuncId t = b.function("main");
  // 32767, then -32768 - 1 ... : the step wraps as the firmware's add does.
  std::vector<Instr> ins;
  for (int i = 0; i < 6; ++i) ins.push_back(wait(I(wrap16(32766 + 2L * i))));
  b.block(t, ins);
  Log log;
  ASSERT_TRUE(reroll_sequences(b.p, log));
  const auto* br = std::get_if<Branch>(&b.p.functions[0].blocks[1].term);
  ASSERT_NE(br, nullptr);
  EXPECT_EQ(br->a, I(wrap16(32766 + 12)));
  EXPECT_EQ(b.p.functions[0].blocks[1].instrs[1].args[1], I(2));
}

TEST(Reroll, OnlyWhereItSavesBytes) {
  // Three waits: 2 x 4 bytes saved is less than the loop's 17.
  Builder three;
  FuncId t = three.function("main");
  three.block(t, {wait(I(10)), wait(I(20)), wait(I(30))});
  Log log;
  EXPECT_FALSE(reroll_sequences(three.p, log));
  // Six waits: 5 x 4 = 20 > 17.
  Builder six;
  t = six.function("main");
  six.block(t, {wait(I(10)), wait(I(20)), wait(I(30)), wait(I(40)), wait(I(50)), wait(I(60))});
  EXPECT_TRUE(reroll_sequences(six.p, log));
}

TEST(Reroll, NeedsOneSteppingValueInPlacesThatTakeAVariable) {
  Log log;
  // Play sound takes only a constant.
  Builder sounds;
  FuncId t = sounds.function("main");
  std::vector<Instr> ins;
  for (int i = 0; i < 6; ++i) ins.push_back(sound(i));
  for (int i = 0; i < 6; ++i) ins.push_back(sound(i));
  sounds.block(t, ins);
  EXPECT_FALSE(reroll_sequences(sounds.p, log));
  // Two values stepping differently would need two counters.
  Builder two;
  VarId g = two.global("g");
  t = two.function("main");
  ins.clear();
  for (int i = 0; i < 8; ++i) {
    ins.push_back(wait(I(10 * i)));
    ins.push_back(set(g, I(3 * i)));
  }
  two.block(t, ins);
  EXPECT_FALSE(reroll_sequences(two.p, log));
  // Copies that are all the same are not a progression.
  Builder same;
  t = same.function("main");
  same.block(t, std::vector<Instr>(10, wait(I(100))));
  EXPECT_FALSE(reroll_sequences(same.p, log));
}

TEST(Reroll, StartupCodeAndRepeatSetupStayInPlace) {
  Builder b;
  FuncId t = b.function("main");
  std::vector<Instr> ins;
  for (int i = 0; i < 8; ++i) ins.push_back(wait(I(i)));
  ins.push_back(loopset(I(3)));
  b.block(t, ins, Jump{1});
  b.block(t, {}, LoopTest{0, 2, 3});
  b.block(t, {filler()}, Jump{1});
  b.block(t, {});
  b.fn(t).startup = 2;  // the first two waits are main's startup code
  b.fn(t).repeats.push_back(Repeat{0, 1, false, true});
  Log log;
  ASSERT_TRUE(reroll_sequences(b.p, log));
  const Function& f = b.p.functions[0];
  ASSERT_EQ(f.blocks.size(), 6u);
  // wait 0, wait 1 stay first; the loop covers 2..7.
  ASSERT_EQ(f.blocks[0].instrs.size(), 3u);
  EXPECT_EQ(f.blocks[0].instrs[1].args[0], I(1));
  EXPECT_EQ(f.blocks[0].instrs[2].args[1], I(2));
  // The loopset moved to the block after the loop, and the repeat with it.
  ASSERT_EQ(f.blocks[2].instrs.size(), 1u);
  EXPECT_EQ(f.blocks[2].instrs[0].op, rcx::Op::SetLoopCounter);
  EXPECT_EQ(f.repeats[0].setup, 2);
  EXPECT_EQ(f.repeats[0].head, 3);
  EXPECT_EQ(std::get<Jump>(f.blocks[2].term).target, 3);
  EXPECT_EQ(std::get<LoopTest>(f.blocks[3].term).body, 4);
}

// Two tasks calling the subroutine at once would share its counter.
TEST(Reroll, SubroutinesAreLeftAlone) {
  Builder b;
  b.function("main");
  b.block(0, {});
  FuncId s = b.function("steps", FuncKind::Sub);
  std::vector<Instr> ins;
  for (int i = 0; i < 8; ++i) ins.push_back(wait(I(10 * i)));
  b.block(s, ins);
  Log log;
  EXPECT_FALSE(reroll_sequences(b.p, log));
  EXPECT_EQ(b.p.functions[1].blocks.size(), 1u);
}

// Two copies are enough when the group is longer than the loop's 17 bytes:
// five `wait 10` then five `wait 11` are two 20-byte copies of one group
// whose constants all step by 1, and save 3 bytes.
TEST(Reroll, TwoLongCopiesAreEnough) {
  Builder b;
  FuncId t = b.function("main");
  std::vector<Instr> ins;
  for (int copy = 0; copy < 2; ++copy)
    for (int j = 0; j < 5; ++j) ins.push_back(wait(I(10 + copy)));
  b.block(t, ins);
  Log log;
  ASSERT_TRUE(reroll_sequences(b.p, log));
  EXPECT_EQ(b.p.functions[0].blocks[1].instrs.size(), 6u);  // five waits and the step
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("2 copies of 5 instructions"), std::string::npos) << log[0];
}
