// Jumps in loops to short blocks become copies (ir/tailcopy.cpp).
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

constexpr int B = 2;

// The copies the pass makes in `f`, given more bytes to spend than any
// test here needs unless told.
std::size_t copies_in(Function& f, int bytes_to_spend = 100) {
  Log log;
  copy_short_jump_targets(f, log, bytes_to_spend);
  return log.size();
}

// A function `main` of the given blocks, with a global x (variable 0).
Function& function_of(Builder& b, std::vector<std::pair<std::vector<Instr>, Terminator>> blocks) {
  b.global("x");
  FuncId f = b.function("main");
  for (auto& [instrs, term] : blocks) b.block(f, std::move(instrs), term);
  return b.fn(f);
}

// while (true) { if (x == 0) then_side; else else_side; join; }: block 0
// the test, 1 the else side, which falls into 2, the join that jumps back
// to the test, and 3 the then side, which jumps to the join: that jump is
// the one a copy saves.
struct Loop {
  Builder b;
  VarId x = b.global("x");
  FuncId f = b.function("main");
  Loop(std::vector<Instr> join, Terminator join_end = Jump{0}) {
    b.block(f, {}, Branch{Cmp::EQ, V(x), I(0), 3, 1});
    b.block(f, {sound(1)}, Jump{2});
    b.block(f, std::move(join), join_end);
    b.block(f, {sound(2)}, Jump{2});
  }
  const Block& then_side() { return b.at(f, 3); }
  std::size_t copies() { return copies_in(b.fn(f)); }
};

}  // namespace

TEST(TailCopy, AJumpInALoopToAShortBlockRunsACopy) {
  // if (x == 0) PlaySound(2); else PlaySound(1); x += 1; }
  Loop l({add(0, I(1))});
  EXPECT_EQ(l.copies(), 1u);
  ASSERT_EQ(l.then_side().instrs.size(), 2u);
  EXPECT_TRUE(same_instr(l.then_side().instrs[1], add(0, I(1))));
  const auto* j = std::get_if<Jump>(&l.then_side().term);
  ASSERT_NE(j, nullptr);
  EXPECT_EQ(j->target, 0);  // straight back to the test
  // The join keeps its code for the side that falls into it, which needs
  // no jump and no copy.
  EXPECT_EQ(l.b.at(l.f, 2).instrs.size(), 1u);
  EXPECT_EQ(l.b.at(l.f, 1).instrs.size(), 1u);
}

TEST(TailCopy, TwoMotorCommandsAreCopied) {
  // SetPower(OUT_A+OUT_C, 7); Fwd(OUT_A+OUT_C); after a line follower's
  // if/else: 6 bytes for the jump saved on that side.
  Loop l({pwr(5, 7), dir(0x80 | 5)});
  EXPECT_EQ(l.copies(), 1u);
  EXPECT_EQ(l.then_side().instrs.size(), 3u);
}

TEST(TailCopy, AWaitStays) {
  // Its time dwarfs the jump's.
  Loop l({wait(I(10))});
  EXPECT_EQ(l.copies(), 0u);
  EXPECT_EQ(l.then_side().instrs.size(), 1u);
}

TEST(TailCopy, CallsStartsLoopCountersAndOtherCommandsStay) {
  Builder b;
  FuncId s = b.function("s", FuncKind::Sub);
  b.block(s, {sound(3)});
  for (const Instr& in : {call(s), start(s), loopset(I(3)), filler()}) {
    Loop l({in});
    EXPECT_EQ(l.copies(), 0u);
  }
}

TEST(TailCopy, MoreThanSevenBytesStay) {
  // Two additions: 10 bytes for a 2-byte jump.
  Loop l({add(0, I(1)), add(0, I(2))});
  EXPECT_EQ(l.copies(), 0u);
  Loop three({out(0x80 | B), out(0x40 | B), out(0x80 | B), out(0x40 | B)});
  EXPECT_EQ(three.copies(), 0u);
}

TEST(TailCopy, TheCopiesOfOneBlockAddSevenBytesInAll) {
  // while (true) { if (x == 0) PlaySound(2); else if (x == 1)
  // PlaySound(3); else PlaySound(1); x += 1; }: two sides jump to the join
  // (5 bytes a copy). Copying it into both would add 10 bytes; an else-if
  // chain of eight sides copied seven times came out larger than nqc's
  // code (117 bytes at -O1, 144 at -O2 against nqc's 117).
  Builder b;
  Function& f = function_of(b, {{{}, Branch{Cmp::EQ, V(0), I(0), 4, 1}},
                                {{}, Branch{Cmp::EQ, V(0), I(1), 5, 2}},
                                {{sound(1)}, Jump{3}},
                                {{add(0, I(1))}, Jump{0}},
                                {{sound(2)}, Jump{3}},
                                {{sound(3)}, Jump{3}}});
  EXPECT_EQ(copies_in(f), 1u);
  EXPECT_EQ(f.blocks[4].instrs.size() + f.blocks[5].instrs.size(), 3u);
  EXPECT_EQ(f.blocks[3].instrs.size(), 1u);
}

TEST(TailCopy, NoCopySpendsMoreThanTheOtherPassesSaved) {
  // while (true) { if (x == 1) x = 4; else x = 6; SetPower(OUT_A+OUT_C, x); }
  // is 31 bytes as lowered and after every other pass, as nqc's; the copy
  // of the power command (4 bytes) made it 35.
  for (int saved : {0, 3}) {
    Loop l({pwr(5, 0)});
    EXPECT_EQ(copies_in(l.b.fn(l.f), saved), 0u) << saved;
    EXPECT_EQ(l.then_side().instrs.size(), 1u);
  }
  Loop l({pwr(5, 0)});
  EXPECT_EQ(copies_in(l.b.fn(l.f), 4), 1u);
}

TEST(TailCopy, ABlockThatFallsIntoTheNextStays) {
  // for (...; ...; i++) { if (c) {...} else {...} }: the join `i++` falls
  // into the loop's test after it. A copy would have to jump to the test
  // itself: the same instructions, 5 bytes more.
  Builder b;
  Function& f = function_of(b, {{{}, Branch{Cmp::EQ, V(0), I(0), 4, 1}},
                                {{sound(1)}, Jump{2}},
                                {{add(0, I(1))}, Jump{3}},
                                {{}, Branch{Cmp::LT, V(0), I(10), 0, 5}},
                                {{sound(2)}, Jump{2}},
                                {{sound(3)}, Exit{}}});
  EXPECT_EQ(copies_in(f), 0u);
  EXPECT_EQ(f.blocks[4].instrs.size(), 1u);
}

TEST(TailCopy, ABlockEndingInATestStays) {
  // A copy of a test costs 7 bytes and more for a jump often not saved.
  Loop l({add(0, I(1))}, Branch{Cmp::EQ, V(0), I(3), 0, 4});
  l.b.block(l.f, {});
  EXPECT_EQ(l.copies(), 0u);
}

TEST(TailCopy, OutsideALoopTheJumpStays) {
  // if (x == 0) PlaySound(2); else PlaySound(1); x += 1; PlaySound(3); and
  // the task ends: the jump runs once, and a copy's bytes would buy nothing.
  Builder b;
  Function& f = function_of(b, {{{}, Branch{Cmp::EQ, V(0), I(0), 3, 1}},
                                {{sound(1)}, Jump{2}},
                                {{add(0, I(1))}, Jump{4}},
                                {{sound(2)}, Jump{2}},
                                {{sound(3)}, Exit{}}});
  EXPECT_EQ(copies_in(f), 0u);
  EXPECT_EQ(f.blocks[3].instrs.size(), 1u);
}

TEST(TailCopy, ABlockWithNoOtherWayInStays) {
  // Block 3 is entered from block 1 alone: a copy would leave it unreached
  // (and the blocks are one straight line in all but their layout).
  Builder b;
  Function& f = function_of(b, {{{}, Branch{Cmp::EQ, V(0), I(0), 2, 1}},
                                {{sound(1)}, Jump{3}},
                                {{sound(2)}, Jump{0}},
                                {{add(0, I(1))}, Jump{0}}});
  EXPECT_EQ(copies_in(f), 0u);
  EXPECT_EQ(f.blocks[1].instrs.size(), 1u);
}

TEST(TailCopy, RawAsmKeepsTheFunctionAsItIs) {
  Loop l({add(0, I(1))});
  l.b.at(l.f, 1).instrs.push_back(Instr{rcx::Op::PlaySound, {I(0x51), I(1)}, true});
  EXPECT_EQ(l.copies(), 0u);
}
