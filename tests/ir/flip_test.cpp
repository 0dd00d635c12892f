// Back-and-forth loops (ir/flip.cpp): which endless loops become one half
// and a direction flip, and which must stay written out.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

constexpr int kA = 1, kB = 2, kFwd = 0x80, kFlip = 0x40;

// Task `main` (after a first block) loops on block 1 through `body`.
struct Loop {
  Builder b;
  FuncId f = 0;
};

Loop loop_of(std::vector<Instr> body) {
  Loop l;
  l.f = l.b.function("main");
  l.b.block(l.f, {sound(9)}, Jump{1});
  l.b.block(l.f, std::move(body), Jump{1});
  return l;
}

// OnFwd(OUT_A+OUT_B); Wait(300); OnRev(OUT_A+OUT_B); Wait(300);
std::vector<Instr> back_and_forth() {
  return {dir(kFwd | kA | kB), out(0x80 | kA | kB), wait(I(300)), dir(kA | kB), out(0x80 | kA | kB), wait(I(300))};
}

bool halved(Loop& l) {
  Log log;
  halve_back_and_forth_loops(l.b.p, log);
  return l.b.fn(l.f).blocks.size() == 3;
}

}  // namespace

TEST(Flip, ABackAndForthLoopBecomesOneHalfAndAFlip) {
  Loop l = loop_of(back_and_forth());
  ASSERT_TRUE(halved(l));
  const Function& f = l.b.fn(l.f);
  // Block 1 sets forward once and enters the loop, block 2.
  ASSERT_EQ(f.blocks[1].instrs.size(), 1u);
  EXPECT_EQ(f.blocks[1].instrs[0].args[0], I(kFwd | kA | kB));
  EXPECT_EQ(std::get<Jump>(f.blocks[1].term).target, 2);
  // The loop: on, wait, flip.
  const auto& loop = f.blocks[2].instrs;
  ASSERT_EQ(loop.size(), 3u);
  EXPECT_EQ(loop[0].op, rcx::Op::SetMotorOnOff);
  EXPECT_EQ(loop[1].op, rcx::Op::Wait);
  EXPECT_EQ(loop[2].op, rcx::Op::SetMotorDirection);
  EXPECT_EQ(loop[2].args[0], I(kFlip | kA | kB));
  EXPECT_EQ(std::get<Jump>(f.blocks[2].term).target, 2);
}

TEST(Flip, WhatComesBeforeTheDirectionRunsFirstThenEveryPass) {
  // PlaySound(1); OnFwd(A); Wait(5); PlaySound(1); OnRev(A); Wait(5):
  // sound, fwd | wait, sound, flip | wait, sound, flip | ...
  Loop l = loop_of({sound(1), dir(kFwd | kA), wait(I(5)), sound(1), dir(kA), wait(I(5))});
  ASSERT_TRUE(halved(l));
  const Function& f = l.b.fn(l.f);
  ASSERT_EQ(f.blocks[1].instrs.size(), 2u);
  EXPECT_EQ(f.blocks[1].instrs[0].op, rcx::Op::PlaySound);
  const auto& loop = f.blocks[2].instrs;
  ASSERT_EQ(loop.size(), 3u);
  EXPECT_EQ(loop[0].op, rcx::Op::Wait);
  EXPECT_EQ(loop[1].op, rcx::Op::PlaySound);
  EXPECT_EQ(loop[2].args[0], I(kFlip | kA));
}

TEST(Flip, AnotherTaskTurningTheOutputsKeepsTheLoop) {
  // The flip counts on the direction the last pass left.
  Loop l = loop_of(back_and_forth());
  FuncId other = l.b.function("other");
  l.b.block(other, {dir(kA)});
  EXPECT_FALSE(halved(l));
  // One that turns another output does not matter.
  Loop m = loop_of(back_and_forth());
  FuncId third = m.b.function("other");
  m.b.block(third, {dir(0x04)});
  EXPECT_TRUE(halved(m));
}

TEST(Flip, MainsStartupCountsOnlyWhenMainIsRestarted) {
  // The loop in task 1; main's startup sets every output forward.
  auto build = [](bool restart) {
    Loop l;
    FuncId main = l.b.function("main");
    l.f = l.b.function("walk");
    l.b.block(main, {dir(kFwd | 7), start(l.f)});
    l.b.fn(main).startup = 1;
    l.b.block(l.f, {sound(9)}, Jump{1});
    l.b.block(l.f, back_and_forth(), Jump{1});
    if (restart) l.b.at(l.f, 0).instrs.push_back(start(main));
    return l;
  };
  Loop once = build(false);
  EXPECT_TRUE(halved(once));
  Loop again = build(true);  // main's startup then runs beside the loop
  EXPECT_FALSE(halved(again));
}

TEST(Flip, ACallOrAnotherTurnInTheLoopKeepsIt) {
  Loop with_call = loop_of(back_and_forth());
  FuncId sub = with_call.b.function("s", FuncKind::Sub);
  with_call.b.block(sub, {sound(1)});
  auto& body = with_call.b.at(with_call.f, 1).instrs;
  body.insert(body.begin() + 2, call(sub));
  body.insert(body.begin() + 6, call(sub));
  EXPECT_FALSE(halved(with_call));
  // dir(AB, rev) in both halves also turns A and B.
  Loop turned = loop_of(back_and_forth());
  auto& b2 = turned.b.at(turned.f, 1).instrs;
  b2.insert(b2.begin() + 2, dir(kA | kB));
  b2.insert(b2.begin() + 6, dir(kA | kB));
  EXPECT_FALSE(halved(turned));
}

TEST(Flip, OnlyHalvesThatDifferInOneOppositeDirection) {
  Loop two = loop_of({dir(kFwd | kA), wait(I(5)), dir(kA), wait(I(6))});  // the waits differ too
  EXPECT_FALSE(halved(two));
  Loop other_outputs = loop_of({dir(kFwd | kA), wait(I(5)), dir(kB), wait(I(5))});
  EXPECT_FALSE(halved(other_outputs));
  Loop flips = loop_of({dir(kFlip | kA), wait(I(5)), dir(kA), wait(I(5))});
  EXPECT_FALSE(halved(flips));
  Loop odd = loop_of({dir(kFwd | kA), wait(I(5)), dir(kA)});
  EXPECT_FALSE(halved(odd));
}
