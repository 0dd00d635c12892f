// The IR passes on hand-built IR.
#include <gtest/gtest.h>

#include <algorithm>

#include "ir/liveness.h"
#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

std::size_t count_ops(const Function& f, rcx::Op op) {
  std::size_t n = 0;
  for (const auto& b : f.blocks)
    for (const auto& in : b.instrs) n += (!in.raw && in.op == op) ? 1 : 0;
  return n;
}

}  // namespace

TEST(Order, ReversePostorderPutsEveryJoinAfterAllWaysIn) {
  // 0 -> {1, 2}; 1 -> 3; 2 -> 3; 3 -> 1 (a loop back); 4 unreachable.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 1, 2});
  b.block(f, {sound(1)}, Jump{3});
  b.block(f, {sound(2)}, Jump{3});
  b.block(f, {}, Branch{Cmp::EQ, V(g), I(1), 1, 5});
  b.block(f, {sound(4)}, Jump{3});
  b.block(f, {});
  auto index = reverse_postorder_index(b.fn(f));
  ASSERT_EQ(index.size(), 6u);
  EXPECT_EQ(index[0], 0);
  EXPECT_LT(index[1], index[3]);
  EXPECT_LT(index[2], index[3]);
  EXPECT_LT(index[3], index[5]);
  EXPECT_EQ(index[4], -1);
}

TEST(Fold, AConstantIsKnownAfterAJoinOnlyWhereItIsStillRead) {
  // t = 5 before an if/else; after the join t is still read, so the use
  // becomes the constant; u = 7 is never read again and is forgotten
  // without changing anything.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  VarId t = b.temp(), u = b.temp();
  b.block(f, {set(t, I(5)), set(u, I(7)), set(g, V(u))}, Branch{Cmp::NE, V(g), I(0), 1, 2});
  b.block(f, {sound(1)}, Jump{3});
  b.block(f, {sound(2)}, Jump{3});
  b.block(f, {set(g, V(t))});
  fold_constants(b.p);
  EXPECT_EQ(b.at(f, 3).instrs[0].args[1], I(5));
  EXPECT_EQ(b.at(f, 0).instrs[2].args[1], I(7));
}

TEST(Fold, AConstantALoopChangesIsNotKnownInTheLoopNorAfterIt) {
  // t = 1; while (g != 0) { g2 = t; t += 1; } g = t: the loop's first pass
  // reaches its head with t = 1, the back edge with t = 2, so neither the
  // body's read nor the one after the loop is the constant. The head's
  // state shrinking must send the blocks after it round again.
  Builder b;
  VarId g = b.global("g"), g2 = b.global("g2");
  FuncId f = b.function("main");
  VarId t = b.temp();
  b.block(f, {set(t, I(1))}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 3});
  b.block(f, {set(g2, V(t)), add(t, I(1))}, Jump{1});
  b.block(f, {set(g, V(t))});
  fold_constants(b.p);
  EXPECT_EQ(b.at(f, 2).instrs[0].args[1], V(t));
  EXPECT_EQ(b.at(f, 3).instrs[0].args[1], V(t));
}

TEST(Fold, TemporaryConstantsReachTheirUse) {
  Builder b;
  VarId t = b.temp();
  FuncId f = b.function("main");
  b.block(f, {set(t, I(3)), add(t, I(4)), wait(V(t))});
  fold_constants(b.p);
  remove_dead_stores(b.p);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 1u);
  EXPECT_EQ(instrs[0].op, rcx::Op::Wait);
  EXPECT_EQ(instrs[0].args[0], I(7));
}

TEST(DeadStore, AnUnusedRandomDrawStaysButWhatFollowsItGoes) {
  // t = Random(10) + 2 with t never read: the draw moves the random source
  // on, so every later draw (and a run with a given seed) depends on it;
  // the add is dead.
  Builder b;
  VarId t = b.local("t");
  FuncId f = b.function("main");
  b.block(f, {set(t, Operand::src(static_cast<int>(rcx::Source::Random), 10)), add(t, I(2)), wait(I(5))});
  remove_dead_stores(b.p);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 2u);
  EXPECT_EQ(instrs[0].op, rcx::Op::SetVariable);
  EXPECT_EQ(instrs[1].op, rcx::Op::Wait);
}

TEST(Fold, GlobalsAreNeverAssumedConstant) {
  // Another task may change a global between two instructions.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {set(g, I(3)), wait(V(g))});
  fold_constants(b.p);
  remove_dead_stores(b.p);
  ASSERT_EQ(b.at(f, 0).instrs.size(), 2u);
  EXPECT_EQ(b.at(f, 0).instrs[1].args[0], V(g));
}

TEST(Fold, ConstantBranchBecomesJumpAndDeadCodeGoes) {
  Builder b;
  VarId t = b.temp();
  FuncId f = b.function("main");
  b.block(f, {set(t, I(1))}, Branch{Cmp::EQ, V(t), I(0), 1, 2});
  b.block(f, {sound(1)}, Jump{3});
  b.block(f, {sound(2)}, Jump{3});
  b.block(f, {sound(3)});
  fold_constants(b.p);
  remove_dead_stores(b.p);
  simplify_cfg(b.fn(f));
  // Only the else path survives, merged into one straight block.
  ASSERT_EQ(b.fn(f).blocks.size(), 1u);
  const auto& instrs = b.fn(f).blocks[0].instrs;
  ASSERT_EQ(instrs.size(), 2u);
  EXPECT_EQ(instrs[0].args[0], I(2));
  EXPECT_EQ(instrs[1].args[0], I(3));
}

TEST(Fold, IdentitiesDisappear) {
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {add(g, I(0)), op(rcx::Op::MultiplyVariable, {V(g), I(1)}), set(g, V(g)), wait(V(g))});
  fold_constants(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 1u);
}

TEST(Fold, DivisionByZeroKeepsTheValueAsTheFirmwareDoes) {
  EXPECT_EQ(arithmetic(rcx::Op::DivideVariable, 17, 0), 17);
  EXPECT_EQ(arithmetic(rcx::Op::DivideVariable, -32768, -1), -32768);
  EXPECT_EQ(arithmetic(rcx::Op::AbsoluteValue, 0, -32768), 32767);
  EXPECT_EQ(arithmetic(rcx::Op::MultiplyVariable, 300, 300), static_cast<std::int16_t>(90000 & 0xffff));
}

TEST(Cfg, JumpsThreadThroughEmptyBlocks) {
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, V(g), I(0), 1, 3});
  b.block(f, {}, Jump{2});
  b.block(f, {}, Jump{4});
  b.block(f, {sound(2)});
  b.block(f, {sound(1)});
  simplify_cfg(b.fn(f));
  // The two empty blocks are gone; the branch goes straight to sound 1.
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 3u);
  const auto& br = std::get<Branch>(blocks[0].term);
  EXPECT_EQ(blocks[static_cast<std::size_t>(br.then)].instrs.at(0).args[0], I(1));
  EXPECT_EQ(blocks[static_cast<std::size_t>(br.otherwise)].instrs.at(0).args[0], I(2));
}

TEST(Cfg, AChainOfTestsWhoseSidesAllMeetFoldsAway) {
  // if (x <= 30) {} else if (x <= 60) {} else if (x <= 90) {}; sound(1):
  // the bodies went (their stores were dead), so every side reaches the
  // sound. The last test folds first, then the one before it, and so on.
  Builder b;
  VarId x = b.global("x");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::LE, V(x), I(30), 1, 2});
  b.block(f, {}, Jump{6});
  b.block(f, {}, Branch{Cmp::LE, V(x), I(60), 3, 4});
  b.block(f, {}, Jump{6});
  b.block(f, {}, Branch{Cmp::LE, V(x), I(90), 5, 6});
  b.block(f, {}, Jump{6});
  b.block(f, {sound(1)});
  simplify_cfg(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].instrs.at(0).args[0], I(1));
}

TEST(Cfg, ATestOfTheRandomSourceStaysWhenItsSidesMeet) {
  // Each read of the random source draws a number: without the test, the
  // numbers drawn after it would differ from the unoptimised program's.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::LE, Operand::src(static_cast<int>(rcx::Source::Random), 9), I(4), 1, 2});
  b.block(f, {}, Jump{2});
  b.block(f, {sound(1)});
  simplify_cfg(b.fn(f));
  EXPECT_TRUE(std::holds_alternative<Branch>(b.fn(f).blocks.at(0).term));
}

namespace {

// switch (x) { case 0: r += 1; T; break; case 1: r += 2; T; break;
// case 2: r += 3; T; break; default: r += 10; } sound(9), with the tail T
// given: blocks 1..3 are the cases, 4 the default, 5 the join.
Builder cases_ending_with(const std::vector<Instr>& tail) {
  Builder b;
  VarId x = b.global("x"), r = b.global("r");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, V(x), I(0), 1, 6});
  for (int k = 1; k <= 3; ++k) {
    std::vector<Instr> body{add(r, I(k))};
    body.insert(body.end(), tail.begin(), tail.end());
    b.block(f, body, Jump{5});
  }
  b.block(f, {add(r, I(10))}, Jump{5});
  b.block(f, {sound(9)});
  b.block(f, {}, Branch{Cmp::EQ, V(x), I(1), 2, 7});
  b.block(f, {}, Branch{Cmp::EQ, V(x), I(2), 3, 4});
  return b;
}

int count_op(const Function& f, rcx::Op op) {
  int n = 0;
  for (const auto& blk : f.blocks)
    for (const auto& in : blk.instrs) n += in.op == op ? 1 : 0;
  return n;
}

}  // namespace

TEST(Cfg, CasesEndingAlikeShareOneCopyOfTheirEnd) {
  Builder b = cases_ending_with({sound(1), wait(I(1))});
  simplify_cfg(b.fn(0));
  const Function& f = b.fn(0);
  EXPECT_EQ(count_op(f, rcx::Op::PlaySound), 2);  // the shared sound(1) and the join's sound(9)
  EXPECT_EQ(count_op(f, rcx::Op::Wait), 1);
  // The shared copy follows the last case, which falls into it.
  for (std::size_t k = 0; k + 1 < f.blocks.size(); ++k) {
    const auto& next = f.blocks[k + 1].instrs;
    if (!next.empty() && next[0].op == rcx::Op::PlaySound && next[0].args[0] == I(1)) {
      EXPECT_EQ(std::get<Jump>(f.blocks[k].term).target, static_cast<BlockId>(k + 1));
    }
  }
}

TEST(Cfg, AShortCommonEndIsNotWorthSharing) {
  // Three copies of a 2-byte sound: 4 bytes saved against up to 5 for
  // jumps that may grow long.
  Builder b = cases_ending_with({sound(1)});
  simplify_cfg(b.fn(0));
  EXPECT_EQ(count_op(b.fn(0), rcx::Op::PlaySound), 4);
}

TEST(Cfg, AnEarlyExitThatIsAllTheCommonEndGoesStraightToTheLastCopy) {
  // while (true) { if (g <= 0) { Off(AC); continue; } Wait(g); Off(AC); }:
  // the early exit is nothing but the 2-byte end the loop's end has too.
  // Shared, the test branches to the loop's copy: the exit's copy and its
  // jump go, and no path runs an instruction more.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {}, Jump{1});
  b.block(f, {}, Branch{Cmp::LE, V(g), I(0), 2, 3});
  b.block(f, {out(0x45)}, Jump{1});
  b.block(f, {wait(V(g)), out(0x45)}, Jump{1});
  // Not in the clean-ups before the motor pass, which may drop one copy.
  simplify_cfg(b.fn(f));
  EXPECT_EQ(count_op(b.fn(f), rcx::Op::SetMotorOnOff), 2);
  simplify_cfg(b.fn(f), true);
  simplify_cfg(b.fn(f), true);
  EXPECT_EQ(count_op(b.fn(f), rcx::Op::SetMotorOnOff), 1);
  EXPECT_EQ(count_op(b.fn(f), rcx::Op::Wait), 1);
}

TEST(Cfg, AnEmptiedBranchThatFellIntoTheJoinKeepsItsCopy) {
  // OnFwd before a loop whose body ends with it too: the copy before the
  // loop falls into the loop's head. Shared, it would need a jump to the
  // loop's copy (and the motor pass could no longer drop either one).
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {}, Jump{1});
  b.block(f, {out(0x85)}, Jump{2});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 3, 4});
  b.block(f, {sound(1), out(0x85)}, Jump{2});
  b.block(f, {sound(2)}, Jump{2});
  simplify_cfg(b.fn(f), true);
  EXPECT_EQ(count_op(b.fn(f), rcx::Op::SetMotorOnOff), 2);
}

TEST(Cfg, AShortEndKeptBesideTwoLongerCopiesIsNotShared) {
  // The same 2-byte end after two blocks that keep code before it: each
  // would jump to the shared copy, a jump more on its path.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {}, Jump{1});
  b.block(f, {}, Branch{Cmp::LE, V(g), I(0), 2, 3});
  b.block(f, {sound(1), out(0x45)}, Jump{1});
  b.block(f, {wait(V(g)), out(0x45)}, Jump{1});
  simplify_cfg(b.fn(f), true);
  EXPECT_EQ(count_op(b.fn(f), rcx::Op::SetMotorOnOff), 2);
}

TEST(Cfg, RawAsmAtTheEndOfBranchesStaysWhereItWasWritten) {
  // asm bytes may hold an offset branch, which would miss after a move.
  Instr raw = op(rcx::Op::SetVariable, {I(0x27), I(0x02)});
  raw.raw = true;
  Builder b = cases_ending_with({sound(1), wait(I(1)), raw});
  simplify_cfg(b.fn(0));
  EXPECT_EQ(count_op(b.fn(0), rcx::Op::Wait), 3);
}

TEST(Cfg, LoopCounterExitIsNotThreadedBackward) {
  // while (true) { repeat (4) sound(1); }: the repeat's exit is an empty
  // block jumping back to the while. Threading it would make the exit a
  // backward target, which the forward-only loop counter reaches only over
  // two jumps; the empty block costs one.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {sound(0)}, Jump{1});
  b.block(f, {loopset(I(4))}, Jump{2});  // while head: repeat setup
  b.block(f, {}, LoopTest{0, 3, 4});
  b.block(f, {sound(1)}, Jump{2});
  b.block(f, {}, Jump{1});  // repeat exit -> while head
  b.fn(f).repeats.push_back(Repeat{1, 2, false, true});
  simplify_cfg(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  const Block* test = nullptr;
  BlockId at = -1;
  for (std::size_t i = 0; i < blocks.size(); ++i)
    if (std::holds_alternative<LoopTest>(blocks[i].term)) test = &blocks[i], at = static_cast<BlockId>(i);
  ASSERT_NE(test, nullptr);
  EXPECT_GT(std::get<LoopTest>(test->term).exit, at);
}

TEST(Rotate, LoopTestMovesBelowTheBody) {
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {sound(0)}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 3});  // test
  b.block(f, {sound(1)}, Jump{1});                    // body, jumps back
  b.block(f, {sound(2)});                             // exit
  rotate_loops(b.fn(f));
  // Layout: entry, body, test, exit; the body falls into the test.
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 4u);
  EXPECT_EQ(std::get<Jump>(blocks[0].term).target, 2);
  EXPECT_EQ(std::get<Jump>(blocks[1].term).target, 2);
  const auto& br = std::get<Branch>(blocks[2].term);
  EXPECT_EQ(br.then, 1);
  EXPECT_EQ(br.otherwise, 3);
}

TEST(Rotate, ATestOfTwoBlocksMovesBelowTheBody) {
  // while (g != 0 && a >= b) body; with a, b variables: a >= b has no
  // one-instruction negation, so with the test on top the loop needs a
  // jump out. Rotated
  // (entry, body, first test, second test, exit) the second test branches
  // back to the body and falls out.
  Builder b;
  VarId g = b.global("g"), x = b.global("a"), y = b.global("b");
  FuncId f = b.function("main");
  b.block(f, {sound(0)}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 4});       // first test
  b.block(f, {sound(3)}, Branch{Cmp::GE, V(x), V(y), 3, 4});  // second test
  b.block(f, {sound(1)}, Jump{1});                          // body
  b.block(f, {sound(2)});                                   // exit
  int before = BlockOrder(b.fn(f)).total();
  rotate_loops(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 5u);
  EXPECT_EQ(std::get<Jump>(blocks[0].term).target, 2);  // into the first test
  EXPECT_EQ(std::get<Jump>(blocks[1].term).target, 2);  // the body falls into it
  const auto& second = std::get<Branch>(blocks[3].term);
  EXPECT_EQ(second.then, 1);
  EXPECT_EQ(second.otherwise, 4);
  EXPECT_EQ(BlockOrder(b.fn(f)).total(), before - 2);
}

TEST(Rotate, ATwoBlockTestMovesAtEqualBytes) {
  // while (g != 0 && a != b): both tests negate, so bytes are equal either
  // way; the whole test still moves so the jump in spans only the body.
  Builder b;
  VarId g = b.global("g"), x = b.global("a"), y = b.global("b");
  FuncId f = b.function("main");
  b.block(f, {sound(0)}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 4});
  b.block(f, {sound(3)}, Branch{Cmp::NE, V(x), V(y), 3, 4});
  b.block(f, {sound(1)}, Jump{1});
  b.block(f, {sound(2)});
  rotate_loops(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 5u);
  ASSERT_EQ(blocks[1].instrs.size(), 1u);
  EXPECT_EQ(blocks[1].instrs[0].args, sound(1).args);  // the body comes first
  EXPECT_EQ(std::get<Branch>(blocks[3].term).then, 1);
}

TEST(Rotate, AnInnerLoopSharingItsTestWithAnEndlessOneMovesItsTestDown) {
  // while (true) { while (g != 0) sound 1; sound 2; }: both loops' latches
  // jump to the test. The outer one leaves through no test, so only the
  // inner one can be rotated: its pass was test, body, jump (3) and is
  // body, test (2). The outer latch still jumps to the test; the jump in
  // is the entry's alone (laid out: entry, body, test, rest).
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {sound(0)}, Jump{1});                    // entry
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 3});  // test
  b.block(f, {sound(1)}, Jump{1});                    // inner body
  b.block(f, {sound(2)}, Jump{1});                    // rest of the outer body
  rotate_loops(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 4u);
  ASSERT_EQ(blocks[1].instrs.size(), 1u);
  EXPECT_EQ(blocks[1].instrs[0].args, sound(1).args);  // the inner body first
  EXPECT_EQ(std::get<Jump>(blocks[0].term).target, 2);
  EXPECT_EQ(std::get<Jump>(blocks[1].term).target, 2);  // falls into the test
  const auto& br = std::get<Branch>(blocks[2].term);
  EXPECT_EQ(br.then, 1);
  EXPECT_EQ(br.otherwise, 3);  // falls into the rest
  EXPECT_EQ(std::get<Jump>(blocks[3].term).target, 2);
}

TEST(Rotate, NoInnerLoopIsRotatedInASubroutine) {
  // The first test's shape in a subroutine: the jump in would run on every
  // call, from wherever the caller loops, and the side that returns may
  // be taken before the inner loop turns once. Nothing moves.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("s", FuncKind::Sub);
  b.block(f, {sound(0)}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 3});
  b.block(f, {sound(1)}, Jump{1});
  b.block(f, {sound(2)}, Jump{1});
  rotate_loops(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 4u);
  EXPECT_TRUE(blocks[1].instrs.empty());  // the test stays second
  EXPECT_EQ(std::get<Branch>(blocks[1].term).then, 2);
}

TEST(Rotate, NoInnerLoopIsRotatedWhereTheJumpInWouldRunOnALoop) {
  // As above, but the block before the test is itself on a loop with it
  // (block 4 goes back to it): rotating would add a jump to that loop's
  // path each time round. Nothing moves.
  Builder b;
  VarId g = b.global("g"), k = b.global("k");
  FuncId f = b.function("main");
  b.block(f, {sound(0)}, Jump{1});
  b.block(f, {sound(5)}, Jump{2});                        // falls into the test
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 3, 4});      // test
  b.block(f, {sound(1)}, Jump{2});                        // inner body
  b.block(f, {sound(2)}, Branch{Cmp::NE, V(k), I(0), 5, 1});
  b.block(f, {sound(3)}, Jump{2});                        // outer latch, to the test
  rotate_loops(b.fn(f));
  const auto& blocks = b.fn(f).blocks;
  ASSERT_EQ(blocks.size(), 6u);
  EXPECT_TRUE(blocks[2].instrs.empty());  // the test stays third
  EXPECT_EQ(std::get<Branch>(blocks[2].term).then, 3);
  EXPECT_EQ(blocks[3].instrs[0].args, sound(1).args);
}

TEST(Layout, TheFalseSideFollowsATestThatOnlyBranchesWhenTrue) {
  // if (a <= b) x = 1; else x = 0; with a, b variables: the negation
  // a > b has no one-instruction test, so the else block moves after it.
  Builder b;
  VarId a = b.global("a"), c = b.global("c"), x = b.global("x");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::LE, V(a), V(c), 1, 2});
  b.block(f, {set(x, I(1))}, Jump{3});  // then
  b.block(f, {set(x, I(0))}, Jump{3});  // else
  b.block(f, {sound(1)});
  place_branch_targets(b.fn(f));
  const auto& br = std::get<Branch>(b.at(f, 0).term);
  EXPECT_EQ(br.otherwise, 1);
  EXPECT_EQ(b.at(f, 1).instrs.at(0).args[1], I(0));
  EXPECT_EQ(br.then, 2);
}

TEST(Layout, ATestWithANegationStaysAsItIs) {
  Builder b;
  VarId a = b.global("a"), x = b.global("x");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::LE, V(a), I(5), 1, 2});  // negation a > 5 is 6 <= a
  b.block(f, {set(x, I(1))}, Jump{3});
  b.block(f, {set(x, I(0))}, Jump{3});
  b.block(f, {sound(1)});
  place_branch_targets(b.fn(f));
  EXPECT_EQ(std::get<Branch>(b.at(f, 0).term).then, 1);
}

TEST(Layout, AnExitInTheMiddleMovesBehindAnEndlessLoop) {
  // if (message == 1) { while (true) sound 2; } else { sound 1; }  laid out
  // else first: its exit jumps over the loop to the task's end. Moved last,
  // it needs no jump, and the test falls into the loop instead.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, Operand::src(15, 0), I(1), 2, 1});
  b.block(f, {sound(1)});             // else, exits
  b.block(f, {sound(2)}, Jump{2});    // then, loops forever
  int before = BlockOrder(b.fn(f)).total();
  place_exit_last(b.fn(f));
  EXPECT_EQ(BlockOrder(b.fn(f)).total(), before - 2);
  EXPECT_TRUE(std::holds_alternative<Exit>(b.at(f, 2).term));
  EXPECT_EQ(b.at(f, 2).instrs.at(0).args[0], I(1));
  EXPECT_EQ(std::get<Jump>(b.at(f, 1).term).target, 1);
}

TEST(Layout, AnExitMovesWithTheBlocksThatOnlyJumpIntoIt) {
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, Operand::src(15, 0), I(1), 3, 1});
  b.block(f, {sound(1)}, Jump{2});
  b.block(f, {sound(3)});
  b.block(f, {sound(2)}, Jump{3});
  place_exit_last(b.fn(f));
  const Function& fn = b.fn(f);
  ASSERT_EQ(fn.blocks.size(), 4u);
  EXPECT_EQ(fn.blocks[1].instrs.at(0).args[0], I(2));
  EXPECT_EQ(fn.blocks[2].instrs.at(0).args[0], I(1));
  EXPECT_EQ(fn.blocks[3].instrs.at(0).args[0], I(3));
  EXPECT_EQ(std::get<Jump>(fn.blocks[2].term).target, 3);
}

TEST(Layout, AnExitStaysWhereMovingItSavesNothing) {
  // if (..) sound 1; (exit) else sound 2; (exit): one of them jumps either way.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, Operand::src(15, 0), I(1), 2, 1});
  b.block(f, {sound(1)});
  b.block(f, {sound(2)});
  place_exit_last(b.fn(f));
  EXPECT_EQ(b.at(f, 1).instrs.at(0).args[0], I(1));
  EXPECT_EQ(b.at(f, 2).instrs.at(0).args[0], I(2));
}

// In a subroutine: a counter left pushed would be read by its caller's
// loop tests.
TEST(Repeat, EscapingLoopCountsInAVariable) {
  Builder b;
  FuncId f = b.function("probe", FuncKind::Sub);
  b.block(f, {loopset(I(5))}, Jump{1});
  b.block(f, {}, LoopTest{0, 2, 3});
  b.block(f, {sound(1)}, Jump{1});
  b.block(f, {});
  b.fn(f).repeats.push_back(Repeat{0, 1, true, true});
  Log log;
  assign_loop_counters(b.p, log);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SetLoopCounter), 0u);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SubtractFromVariable), 1u);
  EXPECT_FALSE(b.fn(f).repeats[0].counter);
}

// In main, a branch out of the body to code that tests no counter: the
// counter stays pushed, no loop test reads it, and the loop keeps it.
TEST(Repeat, MainLeavesTheCounterOfALoopItJumpsOutOf) {
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {loopset(I(5))}, Jump{1});
  b.block(f, {}, LoopTest{0, 2, 3});
  b.block(f, {sound(1)}, Branch{Cmp::EQ, Operand::src(1, 0), I(3), 4, 1});
  b.block(f, {});
  b.block(f, {sound(2)});
  b.fn(f).repeats.push_back(Repeat{0, 1, true, true});
  Log log;
  assign_loop_counters(b.p, log);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SetLoopCounter), 1u);
  EXPECT_TRUE(b.fn(f).repeats[0].counter);
  // Inside an endless loop (the exit block jumping back to the loopset) the
  // jump out would leave a counter each time round.
  b.at(f, 4).term = Jump{0};
  assign_loop_counters(b.p, log);
  EXPECT_FALSE(b.fn(f).repeats[0].counter);
}

TEST(Repeat, FifthNestedLoopCountsInAVariable) {
  Builder b;
  FuncId f = b.function("main");
  // Five nested repeats: setups 0,2,4,6,8 heads 1,3,5,7,9, innermost body 10.
  for (int level = 0; level < 5; ++level) {
    BlockId setup = b.block(f, {loopset(I(2))}, Jump{2 * level + 1});
    BlockId head = b.block(f, {}, LoopTest{level, 2 * level + 2, level == 0 ? 11 : 2 * level - 1});
    b.fn(f).repeats.push_back(Repeat{setup, head, false, true});
  }
  b.block(f, {sound(1)}, Jump{9});
  b.block(f, {});
  Log log;
  assign_loop_counters(b.p, log);
  int counters = 0;
  for (const auto& r : b.fn(f).repeats) counters += r.counter ? 1 : 0;
  EXPECT_EQ(counters, 4);
  EXPECT_FALSE(b.fn(f).repeats[4].counter);
}

TEST(Calls, NestedSubIsInlinedIntoItsCaller) {
  Builder b;
  FuncId main = b.function("main");
  FuncId outer = b.function("outer", FuncKind::Sub);
  FuncId inner = b.function("inner", FuncKind::Sub);
  b.block(main, {call(outer), call(outer)});
  b.block(outer, {sound(1), call(inner), sound(3)});
  b.block(inner, {sound(2)});
  Diagnostics d;
  Log log;
  ASSERT_TRUE(resolve_calls(b.p, OptLevel::O1, d, log));
  EXPECT_EQ(count_ops(b.fn(outer), rcx::Op::CallSubroutine), 0u);
  EXPECT_EQ(count_ops(b.fn(outer), rcx::Op::PlaySound), 3u);
  // inner is no longer called by anyone: dropped.
  EXPECT_TRUE(b.fn(inner).blocks.empty());
  EXPECT_FALSE(log.empty());
}

TEST(Calls, ASubWithATemporaryRunBySeveralTasksIsInlinedWithOwnCopies) {
  // sub both() { t = Timer(0); Wait(t); } called from two tasks: each task
  // gets its own copy and its own temporary.
  Builder b;
  VarId t = b.temp();
  FuncId main = b.function("main"), other = b.function("other");
  FuncId both = b.function("both", FuncKind::Sub);
  b.block(main, {start(other), call(both)});
  b.block(other, {call(both)});
  b.block(both, {set(t, Operand::src(1, 0)), wait(V(t))});
  Diagnostics d;
  Log log;
  ASSERT_TRUE(resolve_calls(b.p, OptLevel::O1, d, log));
  EXPECT_TRUE(b.fn(both).blocks.empty());
  auto temp_of = [&](FuncId f) {
    for (const auto& blk : b.fn(f).blocks)
      for (const auto& in : blk.instrs)
        if (in.op == rcx::Op::Wait) return in.args[0].value;
    return -1;
  };
  EXPECT_GE(temp_of(main), 0);
  EXPECT_GE(temp_of(other), 0);
  EXPECT_NE(temp_of(main), temp_of(other));
  Diagnostics slot_diags;
  auto slots = allocate_slots(b.p, slot_diags);
  ASSERT_FALSE(slots.empty());
  EXPECT_NE(slots[static_cast<std::size_t>(temp_of(main))], slots[static_cast<std::size_t>(temp_of(other))]);
}

TEST(Calls, EveryInlinedCopyKeepsTheLocalTheSubReadsBeforeWriting) {
  // sub count_up() { seen = k; k = seen + 10; } inlined at both calls of
  // main: k carries from one copy to the next as it does from one call to
  // the next. The last copy too: by the time its body is copied the call
  // is gone and the sub is called nowhere.
  Builder b;
  VarId seen = b.global("seen"), k = b.local("k");
  FuncId main = b.function("main");
  FuncId s = b.function("count_up", FuncKind::Sub);
  b.block(main, {call(s), call(s)});
  b.block(s, {set(seen, V(k)), set(k, V(seen)), add(k, I(10))});
  auto inline_first_call = [&] {
    for (std::size_t blk = 0; blk < b.fn(main).blocks.size(); ++blk)
      for (std::size_t i = 0; i < b.at(main, static_cast<BlockId>(blk)).instrs.size(); ++i)
        if (callee_of(b.at(main, static_cast<BlockId>(blk)).instrs[i]) == s) {
          inline_call(b.p, main, static_cast<BlockId>(blk), i);
          return true;
        }
    return false;
  };
  ASSERT_TRUE(inline_first_call());
  ASSERT_TRUE(inline_first_call());
  EXPECT_EQ(count_ops(b.fn(main), rcx::Op::CallSubroutine), 0u);
  std::size_t reads_of_k = 0, writes_of_k = 0;
  for (const auto& blk : b.fn(main).blocks)
    for (const auto& in : blk.instrs) {
      for (VarId v : uses_of(in).reads) reads_of_k += v == k ? 1 : 0;
      for (VarId v : uses_of(in).writes) writes_of_k += v == k ? 1 : 0;
    }
  EXPECT_EQ(reads_of_k, 4u);   // seen = k, and add k's read of itself, per copy
  EXPECT_EQ(writes_of_k, 4u);  // set k and add k, per copy
  EXPECT_EQ(b.p.vars.size(), 2u) << "an inlined copy got a variable of its own";
}

TEST(Liveness, AnUncalledSubStillReportsWhatItReadsBeforeWriting) {
  Builder b;
  VarId seen = b.global("seen"), k = b.local("k");
  b.function("main");
  FuncId s = b.function("count_up", FuncKind::Sub);
  b.block(s, {set(seen, V(k)), set(k, V(seen))});
  auto calls = call_effects(b.p);
  EXPECT_TRUE(calls.reads[static_cast<std::size_t>(s)].has(k));
}

TEST(Calls, ASubOnlyUsingGlobalsStaysASub) {
  Builder b;
  VarId g = b.global("g");
  FuncId main = b.function("main"), other = b.function("other");
  FuncId both = b.function("both", FuncKind::Sub);
  b.block(main, {start(other), call(both)});
  b.block(other, {call(both)});
  b.block(both, {add(g, I(1)), wait(V(g)), sound(1), sound(2), sound(3)});
  Diagnostics d;
  Log log;
  ASSERT_TRUE(resolve_calls(b.p, OptLevel::O1, d, log));
  EXPECT_FALSE(b.fn(both).blocks.empty());
}

TEST(Calls, RecursionIsReportedWithTheCycle) {
  Builder b;
  FuncId main = b.function("main");
  FuncId x = b.function("x", FuncKind::Sub);
  FuncId y = b.function("y", FuncKind::Sub);
  b.block(main, {call(x)});
  b.block(x, {call(y)});
  b.block(y, {call(x)});
  Diagnostics d;
  Log log;
  EXPECT_FALSE(resolve_calls(b.p, OptLevel::O1, d, log));
  ASSERT_EQ(d.error_count(), 1u);
  EXPECT_NE(d.all()[0].message.find("x -> y -> x"), std::string::npos) << d.all()[0].message;
}

TEST(Calls, AtMostEightSubsRemain) {
  Builder b;
  FuncId main = b.function("main");
  std::vector<Instr> calls;
  for (int i = 0; i < 10; ++i) {
    FuncId s = b.function("s" + std::to_string(i), FuncKind::Sub);
    std::vector<Instr> body(static_cast<std::size_t>(i + 1), sound(i % 6));
    b.block(s, body);
    calls.push_back(call(s));
    calls.push_back(call(s));
  }
  b.block(main, calls);
  Diagnostics d;
  Log log;
  ASSERT_TRUE(resolve_calls(b.p, OptLevel::O1, d, log));
  int subs = 0;
  for (const auto& f : b.p.functions) subs += (f.kind == FuncKind::Sub && !f.blocks.empty()) ? 1 : 0;
  EXPECT_EQ(subs, 8);
  // The two smallest (s0, s1) were inlined: cheapest first.
  EXPECT_TRUE(b.fn(1).blocks.empty());
  EXPECT_TRUE(b.fn(2).blocks.empty());
}

TEST(Slots, DisjointTemporariesShareASlot) {
  Builder b;
  VarId t1 = b.temp(), t2 = b.temp();
  FuncId f = b.function("main");
  b.block(f, {set(t1, Operand::src(1, 0)), wait(V(t1)), set(t2, Operand::src(1, 1)), wait(V(t2))});
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  ASSERT_EQ(slots.size(), 2u);
  EXPECT_EQ(slots[0], slots[1]);
}

TEST(Slots, OverlappingTemporariesDoNot) {
  Builder b;
  VarId t1 = b.temp(), t2 = b.temp();
  FuncId f = b.function("main");
  b.block(f, {set(t1, Operand::src(1, 0)), set(t2, Operand::src(1, 1)), wait(V(t1)), wait(V(t2))});
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  ASSERT_EQ(slots.size(), 2u);
  EXPECT_NE(slots[0], slots[1]);
}

TEST(Slots, TasksNeverShare) {
  Builder b;
  VarId t1 = b.temp(), t2 = b.temp();
  FuncId m = b.function("main"), o = b.function("other");
  b.block(m, {set(t1, Operand::src(1, 0)), wait(V(t1))});
  b.block(o, {set(t2, Operand::src(1, 1)), wait(V(t2))});
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  EXPECT_NE(slots[0], slots[1]);
}

TEST(Slots, ASubsVariablesAvoidWhatIsLiveAcrossItsCall) {
  Builder b;
  VarId kept = b.temp(), sub_local = b.temp(), after = b.temp();
  FuncId m = b.function("main");
  FuncId s = b.function("s", FuncKind::Sub);
  b.block(m, {set(kept, Operand::src(1, 0)), call(s), wait(V(kept)), set(after, Operand::src(1, 2)), wait(V(after))});
  b.block(s, {set(sub_local, Operand::src(1, 1)), wait(V(sub_local))});
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  EXPECT_NE(slots[static_cast<std::size_t>(kept)], slots[static_cast<std::size_t>(sub_local)]);
  // `after` is born after the call returned: it may reuse the sub's slot.
  EXPECT_EQ(slots[static_cast<std::size_t>(after)], slots[static_cast<std::size_t>(kept)]);
}

TEST(Slots, AVariableSeveralTasksUseGetsASlotOfItsOwnAndAWarning) {
  // What inlining cannot fix any more (the allocator sees the program as
  // it is): the shared temporary still gets a slot, shared with nothing.
  Builder b;
  VarId t = b.temp(), u = b.temp(), w = b.temp();
  FuncId main = b.function("main"), other = b.function("other");
  FuncId both = b.function("both", FuncKind::Sub);
  b.block(main, {set(u, Operand::src(1, 0)), wait(V(u)), start(other), call(both)});
  b.block(other, {set(w, Operand::src(1, 1)), wait(V(w)), call(both)});
  b.block(both, {set(t, Operand::src(1, 2)), wait(V(t))});
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  ASSERT_EQ(slots.size(), 3u);
  EXPECT_NE(slots[0], slots[1]);
  EXPECT_NE(slots[0], slots[2]);
  EXPECT_NE(slots[1], slots[2]);
  EXPECT_FALSE(d.has_errors());
  ASSERT_EQ(d.all().size(), 1u);
  EXPECT_NE(d.all()[0].message.find("'both'"), std::string::npos);
  EXPECT_EQ(d.all()[0].warning, WarningKind::SharedSubroutine);
}

TEST(Slots, ReservedSlotsAreSkipped) {
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {set(g, I(1))});
  b.p.reserved_slots = 0x7;
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  EXPECT_EQ(slots[static_cast<std::size_t>(g)], 3);
}

TEST(Slots, EveryGlobalHasNqcsSlotUsedOrNot) {
  // nqc: the lowest free slot in declaration order, unused globals too; a
  // temporary never takes a global's slot.
  Builder b;
  VarId unused = b.global("unused");
  VarId t = b.temp();
  VarId g = b.global("g");
  VarId late = b.global("late");
  FuncId f = b.function("main");
  b.block(f, {set(t, Operand::src(1, 0)), set(late, V(t)), set(g, I(2))});
  b.p.reserved_slots = 0x2;
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  ASSERT_EQ(slots.size(), 4u);
  EXPECT_EQ(slots[static_cast<std::size_t>(unused)], 0);
  EXPECT_EQ(slots[static_cast<std::size_t>(g)], 2);
  EXPECT_EQ(slots[static_cast<std::size_t>(late)], 3);
  EXPECT_EQ(slots[static_cast<std::size_t>(t)], 4);
}

TEST(DeadStore, ALocalReadBeforeItIsWrittenKeepsItsLastValueForTheNextRun) {
  // sub { seen = k; k = seen + 10; }: the next call reads k, so the write
  // at the end is not dead.
  Builder b;
  VarId seen = b.global("seen"), k = b.local("k");
  FuncId f = b.function("count_up");
  b.block(f, {set(seen, V(k)), set(k, V(seen)), add(k, I(10))});
  remove_dead_stores(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 3u);
}

TEST(ReadBeforeWrite, WarnsOnceAtTheRead) {
  Builder b;
  VarId seen = b.global("seen"), k = b.local("k"), j = b.local("j");
  FuncId f = b.function("main");
  SourceSpan at{{1, 5, 3}, {1, 5, 12}};
  Instr read = set(seen, V(k));
  read.span = b.p.add_span(at);
  b.block(f, {set(j, I(1)), set(seen, V(j)), read, set(k, I(3)), set(seen, V(k))}, Branch{Cmp::NE, V(k), I(0), 1, 1});
  b.block(f, {set(seen, V(k))});
  Diagnostics d;
  warn_reads_before_writes(b.p, d);
  ASSERT_EQ(d.all().size(), 1u);
  EXPECT_EQ(d.all()[0].severity, Severity::Warning);
  EXPECT_NE(d.all()[0].message.find("'k' is read before it is written"), std::string::npos);
  EXPECT_EQ(d.all()[0].span.begin.line, 5u);
}

TEST(ReadBeforeWrite, NotesWhereTheLocalIsDeclared) {
  // A local of an inline function is read in the caller's code, where the
  // call is: the warning is at the call, so a note names the local's own
  // declaration, inside the function.
  Builder b;
  VarId seen = b.global("seen"), p = b.local("p");
  SourceSpan declared{{1, 3, 7}, {1, 3, 8}};
  b.p.vars[static_cast<std::size_t>(p)].span = declared;
  FuncId f = b.function("main");
  SourceSpan call{{1, 11, 3}, {1, 11, 19}};
  Instr read = set(seen, V(p));
  read.span = b.p.add_span(call);
  b.block(f, {read});
  Diagnostics d;
  warn_reads_before_writes(b.p, d);
  ASSERT_EQ(d.all().size(), 1u);
  EXPECT_EQ(d.all()[0].span.begin.line, 11u);
  ASSERT_EQ(d.all()[0].notes.size(), 1u);
  EXPECT_EQ(d.all()[0].notes[0].span.begin.line, 3u);
  EXPECT_EQ(d.all()[0].notes[0].message, "'p' is declared here");
}

TEST(ReadBeforeWrite, AbsAndSignOverwriteTheirDestination) {
  // x = abs(g); y = sign(g): abs and sgn compute from their source alone,
  // so neither local is read before it is written (nqc's `x ||= e` and
  // `x +-= e` are these instructions too).
  Builder b;
  VarId g = b.global("g"), x = b.local("x"), y = b.local("y");
  FuncId f = b.function("main");
  b.block(f, {op(rcx::Op::AbsoluteValue, {V(x), V(g)}), op(rcx::Op::SignVariable, {V(y), V(g)}), set(g, V(x)),
              add(g, V(y))});
  Diagnostics d;
  warn_reads_before_writes(b.p, d);
  EXPECT_TRUE(d.all().empty());
  for (const Instr& in : b.at(f, 0).instrs) {
    if (in.op != rcx::Op::AbsoluteValue && in.op != rcx::Op::SignVariable) continue;
    VarUse u = uses_of(in);
    EXPECT_EQ(std::count(u.reads.begin(), u.reads.end(), in.args[0].value), 0);
    EXPECT_EQ(std::count(u.writes.begin(), u.writes.end(), in.args[0].value), 1);
  }
}

TEST(Slots, AnAbsTemporaryIsNotLiveBeforeItIsComputed) {
  // t1 = g; t1 += g; g = t1; t2 = sign(g); g += t2: t2 lives from its sgn
  // to the add only, so it can have t1's slot once t1 is dead. With abs
  // and sgn taken as reading their destination, t2 was live from the
  // entry and needed a slot of its own (nqc's code for the same program
  // fitted 30 globals and 2 temporaries; rcxc asked for a 33rd slot).
  Builder b;
  VarId g = b.global("g"), t1 = b.temp(), t2 = b.temp();
  FuncId f = b.function("main");
  b.block(f, {set(t1, V(g)), add(t1, V(g)), set(g, V(t1)), op(rcx::Op::SignVariable, {V(t2), V(g)}), add(g, V(t2))});
  Diagnostics d;
  auto slots = allocate_slots(b.p, d);
  ASSERT_FALSE(slots.empty());
  EXPECT_EQ(slots[static_cast<std::size_t>(t1)], 1);
  EXPECT_EQ(slots[static_cast<std::size_t>(t2)], 1);
}

TEST(Slots, ExhaustionNamesTheHolders) {
  Builder b;
  FuncId f = b.function("main");
  std::vector<Instr> body;
  for (int i = 0; i < 33; ++i) body.push_back(set(b.global("g" + std::to_string(i)), I(i)));
  b.block(f, body);
  Diagnostics d;
  EXPECT_TRUE(allocate_slots(b.p, d).empty());
  ASSERT_EQ(d.error_count(), 1u);
  const auto& diag = d.all()[0];
  EXPECT_NE(diag.message.find("'g32'"), std::string::npos);
  // The 32 globals in a row are one note (faithfulness round 15's lm04 had
  // 32 notes, one a slot).
  ASSERT_EQ(diag.notes.size(), 1u);
  std::string names;
  for (int i = 0; i < 32; ++i) names += (i ? ", 'g" : "'g") + std::to_string(i) + "'";
  EXPECT_EQ(diag.notes[0].message, "slots 0 to 31 are held by " + names);
}

// Only runs of three or more slots each held by one named variable are
// joined: a reserved slot and a run of two keep a note a slot.
TEST(Slots, ExhaustionJoinsOnlyRunsOfNamedHolders) {
  Builder b;
  b.p.reserved_slots = (1u << 2) | (1u << 5);
  FuncId f = b.function("main");
  std::vector<Instr> body;
  for (int i = 0; i < 31; ++i) body.push_back(set(b.global("g" + std::to_string(i)), I(i)));
  b.block(f, body);
  Diagnostics d;
  EXPECT_TRUE(allocate_slots(b.p, d).empty());
  ASSERT_EQ(d.error_count(), 1u);
  std::vector<std::string> notes;
  for (const auto& n : d.all()[0].notes) notes.push_back(n.message.substr(0, 36));
  EXPECT_EQ(notes, (std::vector<std::string>{"slot 0 is held by 'g0'", "slot 1 is held by 'g1'",
                                             "slot 2 is held by #pragma reserve", "slot 3 is held by 'g2'",
                                             "slot 4 is held by 'g3'", "slot 5 is held by #pragma reserve",
                                             "slots 6 to 31 are held by 'g4', 'g5'"}));
}

TEST(Motors, RepeatedCommandsOfTheOnlyCommandingTaskGo) {
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {dir(0x81), out(0x81), wait(I(10)), dir(0x81), out(0x81), wait(I(10)), dir(0x01)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 5u);  // the second forward/on pair is gone
}

TEST(Motors, OutputsOfTwoTasksAreLeftAlone) {
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {start(g), out(0x81), wait(I(10)), out(0x81)});
  b.block(g, {out(0x41)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 4u);
}

TEST(Motors, WhatEveryOtherTaskAlsoSetsIsStillKnown) {
  // Both tasks only ever switch A and C on; `other` also reverses C. In
  // main, A stays on whatever `other` does, so the second `on A` goes; C's
  // direction may change under main, so its second `fwd C` stays.
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {start(g), out(0x85), dir(0x84), wait(I(10)), out(0x81), dir(0x84)});
  b.block(g, {out(0x85), dir(0x04)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SetMotorOnOff), 1u);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SetMotorDirection), 2u);
}

TEST(Motors, MainIsAloneUntilItStartsATask) {
  // Another task commands A too, but only once main has started it.
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {out(0x81), wait(I(10)), out(0x81), start(g), out(0x81), wait(I(10)), out(0x81)});
  b.block(g, {out(0x41)});
  remove_redundant_motor_commands(b.p);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 6u);  // only the second `on`, before the start, goes
  EXPECT_EQ(instrs[2].op, rcx::Op::StartTask);
}

TEST(Motors, RestartedMainIsNeverAlone) {
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {out(0x81), wait(I(10)), out(0x81), start(g)});
  b.block(g, {out(0x41), start(f)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 4u);
}

TEST(Motors, AStartedTaskBeginsWithWhatItsStarterKnew) {
  // main sets B forward and starts `other`, which switches B forward and on:
  // nobody else commands B, so the direction is already set.
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {dir(0x82), start(g), wait(I(10))});
  b.block(g, {dir(0x82), out(0x82)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(count_ops(b.fn(g), rcx::Op::SetMotorDirection), 0u);
  EXPECT_EQ(count_ops(b.fn(g), rcx::Op::SetMotorOnOff), 1u);
}

TEST(Motors, WhatTheStarterChangesLaterIsNotKnownToTheStartedTask) {
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {dir(0x82), start(g), dir(0x02)});
  b.block(g, {wait(I(10)), dir(0x82)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(count_ops(b.fn(g), rcx::Op::SetMotorDirection), 1u);
}

TEST(Motors, ATaskStartedFromTwoPlacesKnowsWhatBothAgreeOn) {
  // main starts `other` with B forward; `other` restarts itself with B
  // reversed and A still forward.
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {dir(0x83), start(g)});
  b.block(g, {dir(0x81), dir(0x82), wait(I(10)), dir(0x02), start(g)});
  remove_redundant_motor_commands(b.p);
  const auto& instrs = b.at(g, 0).instrs;
  ASSERT_EQ(instrs.size(), 4u);  // A forward goes, B forward stays
  EXPECT_EQ(instrs[0].args[0].value, 0x82);
}

TEST(Motors, ATaskNobodyStartsIsLeftAlone) {
  Builder b;
  FuncId f = b.function("main"), g = b.function("other");
  b.block(f, {dir(0x82), wait(I(10))});
  b.block(g, {dir(0x82), wait(I(10)), dir(0x82)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(count_ops(b.fn(g), rcx::Op::SetMotorDirection), 1u);  // only the repeat goes
}

TEST(Motors, ASubStartsFromWhatItsCallsHave) {
  // main: OnFwd(A); sub(); Wait; sub();  sub: OnRev(A); Wait; OnFwd(A).
  // Every call finds A on: the sub's `on` commands go, its directions stay.
  Builder b;
  FuncId f = b.function("main");
  FuncId s = b.function("turn", FuncKind::Sub);
  b.block(f, {dir(0x81), out(0x81), call(s), wait(I(10)), call(s), out(0x41)});
  b.block(s, {dir(0x01), out(0x81), wait(I(5)), dir(0x81), out(0x81)});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(count_ops(b.fn(s), rcx::Op::SetMotorOnOff), 0u);
  EXPECT_EQ(count_ops(b.fn(s), rcx::Op::SetMotorDirection), 2u);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SetMotorOnOff), 2u);  // on, and the final off
}

TEST(Motors, ASubCalledWithDifferentStatesKeepsItsCommands) {
  Builder b;
  FuncId f = b.function("main");
  FuncId s = b.function("go", FuncKind::Sub);
  b.block(f, {out(0x81), call(s), out(0x41), call(s)});
  b.block(s, {out(0x81), wait(I(5))});
  remove_redundant_motor_commands(b.p);
  EXPECT_EQ(count_ops(b.fn(s), rcx::Op::SetMotorOnOff), 1u);
  EXPECT_EQ(count_ops(b.fn(f), rcx::Op::SetMotorOnOff), 2u);
}

TEST(Motors, RunsOfCommandsMerge) {
  Builder b;
  FuncId f = b.function("main");
  // OnRev(A); OnFwd(C): two directions, one on.
  b.block(f, {dir(0x01), out(0x81), dir(0x84), out(0x84), wait(I(5))});
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 4u);
  EXPECT_EQ(instrs[2].op, rcx::Op::SetMotorOnOff);
  EXPECT_EQ(instrs[2].args[0], I(0x85));
  EXPECT_EQ(instrs[3].op, rcx::Op::Wait);
}

// The merged directions, powers and switches come in the order the window
// first set each output, so an output written first changes first, as in
// the code as written and nqc's: ordered by value, C's reverse (0x00) went
// before A's forward (0x80) and A's direction came an instruction later.
TEST(Motors, MergedCommandsKeepTheOrderTheOutputsWereWritten) {
  Builder b;
  FuncId f = b.function("main");
  // Fwd(A); Rev(C); SetPower(C, 5); SetPower(A, 2); On(A + C); then the
  // same with A on first: OnFwd(A); OnRev(C) (one direction each, one on).
  b.block(f, {dir(0x81), dir(0x04), pwr(4, 5), pwr(1, 2), out(0x85), wait(I(5)), dir(0x81), out(0x81), dir(0x04),
              out(0x84), wait(I(5))});
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 10u);
  // directions first (each output's direction came before its power)
  EXPECT_EQ(instrs[0].op, rcx::Op::SetMotorDirection);
  EXPECT_EQ(instrs[0].args[0], I(0x81));  // A forward first
  EXPECT_EQ(instrs[1].args[0], I(0x04));  // then C reverse
  EXPECT_EQ(instrs[2].op, rcx::Op::SetMotorPower);
  EXPECT_EQ(instrs[2].args[0], I(4));  // C's power was set first
  EXPECT_EQ(instrs[3].args[0], I(1));
  EXPECT_EQ(instrs[4].op, rcx::Op::SetMotorOnOff);
  EXPECT_EQ(instrs[4].args[0], I(0x85));
  EXPECT_EQ(instrs[6].op, rcx::Op::SetMotorDirection);
  EXPECT_EQ(instrs[6].args[0], I(0x81));  // A forward first
  EXPECT_EQ(instrs[7].args[0], I(0x04));
  EXPECT_EQ(instrs[8].op, rcx::Op::SetMotorOnOff);
  EXPECT_EQ(instrs[8].args[0], I(0x85));
}

TEST(Motors, MergedBlocksKeepEveryOtherInstructionInOrder) {
  // The block is rewritten in place: the startup code stays first as it
  // is, a window's neutral instructions come before its merged commands,
  // and the windows after a merge, merged or not, keep their places.
  Builder b;
  FuncId f = b.function("main");
  VarId x = b.local("x");
  b.fn(f).startup = 2;
  b.block(f, {dir(0x01), out(0x81),                            // startup: never merged
              dir(0x01), set(x, I(3)), out(0x81), dir(0x84), out(0x84),  // one window: neutral, then 1 command
              wait(I(5)),                                           // ends it
              out(0x81),                                            // alone: kept (the off undoes it)
              out(0x41), sound(1), pwr(1, 3), pwr(4, 3), add(x, I(1))});  // A off first, one power
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 12u);
  EXPECT_EQ(instrs[0].op, rcx::Op::SetMotorDirection);
  EXPECT_EQ(instrs[1].args[0], I(0x81));
  EXPECT_EQ(instrs[2].op, rcx::Op::SetVariable);
  EXPECT_EQ(instrs[3].op, rcx::Op::SetMotorDirection);  // A reversed, C forward: two directions
  EXPECT_EQ(instrs[4].op, rcx::Op::SetMotorDirection);
  EXPECT_EQ(instrs[5].op, rcx::Op::SetMotorOnOff);
  EXPECT_EQ(instrs[5].args[0], I(0x85));
  EXPECT_EQ(instrs[6].op, rcx::Op::Wait);
  EXPECT_EQ(instrs[7].args[0], I(0x81));
  EXPECT_EQ(instrs[8].op, rcx::Op::PlaySound);
  EXPECT_EQ(instrs[9].args[0], I(0x41));
  EXPECT_EQ(instrs[10].op, rcx::Op::SetMotorPower);
  EXPECT_EQ(instrs[10].args[0], I(5));
  EXPECT_EQ(instrs[11].op, rcx::Op::AddToVariable);
}

TEST(Motors, OutputsThatStopDoSoBeforeTheirDirectionChanges) {
  // Float(OUT_B+OUT_C); OnRev(OUT_A); Rev(OUT_C); with C running: merged,
  // C must float before it is reversed, or it would run backwards for an
  // instruction (a glitch the program never had).
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {out(0x06), dir(0x01), out(0x81), dir(0x04)});
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 3u);
  EXPECT_EQ(instrs[0].args[0], I(0x06));  // B and C float
  EXPECT_EQ(instrs[1].args[0], I(0x05));  // A and C reversed
  EXPECT_EQ(instrs[2].args[0], I(0x81));  // A on
}

TEST(Motors, AnOutputStoppedBeforeAPowerChangeStaysStopped) {
  // Off(B); SetPower(A+B+C, 1); Off(A+B+C); with B running: B stops before
  // the power changes, so the merged commands must stop it first too, or
  // it would run at power 1 for an instruction (random motor program 10890
  // against nqc's code).
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {out(0x42), pwr(7, 1), out(0x47)});
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  // Merged, B would have to stop early and A and C late: no fewer commands,
  // so they stay as written (before, B's stop moved after the power change).
  ASSERT_EQ(instrs.size(), 3u);
  EXPECT_EQ(instrs[0].op, rcx::Op::SetMotorOnOff);
  EXPECT_EQ(instrs[0].args[0], I(0x42));  // B off first
  EXPECT_EQ(instrs[1].op, rcx::Op::SetMotorPower);
  EXPECT_EQ(instrs[2].op, rcx::Op::SetMotorOnOff);
}

TEST(Motors, ARunningOutputSeesDirectionAndPowerInTheirOrder) {
  // On(A+B+C); OnRev(C); OnRev(B+C); SetPower(A+B+C, 3): B and C run
  // backwards at full power, then at 3. Merged, the direction must still
  // come before the power, or they would run forwards at 3 for an
  // instruction (random motor program 63429 against nqc's code).
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {out(0x87), dir(0x04), dir(0x06), pwr(7, 3)});
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 3u);
  EXPECT_EQ(instrs[0].args[0], I(0x87));
  EXPECT_EQ(instrs[1].op, rcx::Op::SetMotorDirection);
  EXPECT_EQ(instrs[2].op, rcx::Op::SetMotorPower);
}

TEST(Motors, OutputsThatSawSettingsInOppositeOrdersAreNotMerged) {
  // A (maybe running) is reversed then slowed; B is slowed then reversed:
  // no one order of the merged commands shows both as they were.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {dir(0x01), pwr(1, 3), pwr(2, 3), dir(0x02), dir(0x04)});
  merge_motor_commands(b.fn(f), b.p.vars);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 5u);
}

TEST(Motors, APulseIsNeverMergedAway) {
  // On(A); Off(A); and Fwd(A); Rev(A): each sets one field of A to two
  // values; merged, the on-time (or the forward run) would vanish.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {out(0x81), out(0x41), dir(0x81), dir(0x01)});
  merge_motor_commands(b.fn(f), b.p.vars);
  EXPECT_EQ(b.at(f, 0).instrs.size(), 4u);
}

TEST(Motors, AWindowEndsWhereAFieldWouldChangeAgain) {
  // OnRev(A); OnFwd(C); Off(A): the first two merge (one "on"), the off
  // that undoes A's on stays after them.
  Builder b;
  FuncId f = b.function("main");
  b.block(f, {dir(0x01), out(0x81), dir(0x84), out(0x84), out(0x41)});
  merge_motor_commands(b.fn(f), b.p.vars);
  const auto& instrs = b.at(f, 0).instrs;
  ASSERT_EQ(instrs.size(), 4u);
  EXPECT_EQ(instrs[2].args[0], I(0x85));
  EXPECT_EQ(instrs[3].args[0], I(0x41));
}

// Past eight subroutines the cheapest to inline go first (bytes added:
// calls x size - size - the calls' bytes), equals in order of number; the
// choice is worked out once for all of them (it used to ask the whole
// program again for every subroutine at every step: 1 000 subroutines took
// 41 s), so this pins the order that must not change.
TEST(Calls, PastEightSubroutinesTheCheapestGoFirstEqualsByNumber) {
  Builder b;
  FuncId main = b.function("main");
  // (calls, sounds in the body) per subroutine s0..s10.
  const std::vector<std::pair<int, int>> shape{{3, 3}, {1, 5}, {1, 1}, {2, 2}, {3, 4}, {3, 4},
                                               {3, 4}, {3, 4}, {3, 4}, {3, 4}, {3, 4}};
  std::vector<Instr> calls;
  for (std::size_t i = 0; i < shape.size(); ++i) {
    FuncId s = b.function("s" + std::to_string(i), FuncKind::Sub);
    b.block(s, std::vector<Instr>(static_cast<std::size_t>(shape[i].second), sound(1)));
    for (int c = 0; c < shape[i].first; ++c) calls.push_back(call(s));
  }
  b.block(main, calls);
  Diagnostics d;
  Log log;
  ASSERT_TRUE(resolve_calls(b.p, OptLevel::O0, d, log));
  std::vector<std::string> inlined;
  for (const auto& line : log)
    if (line.find("more than 8 subroutines") != std::string::npos) inlined.push_back(line.substr(0, line.find(" inlined")));
  EXPECT_EQ(inlined, (std::vector<std::string>{"sub s1", "sub s2", "sub s3"}));
}

namespace {

// Flattening replaces all calls of a subroutine in one pass over it (a
// block split at each of its calls): the result must be what replacing
// them one at a time, first call first, gives, blocks, variables and
// counter loops alike, with calls in a loop's setup block, before and
// after other instructions, in the loop's body and at a block's end.
TEST(Calls, InliningEveryCallAtOnceEqualsOneAtATime) {
  auto build = [](Builder& b, FuncId& outer) {
    VarId x = b.global("x");
    VarId t = b.temp();
    FuncId main = b.function("main");
    outer = b.function("outer", FuncKind::Sub);
    FuncId s = b.function("s", FuncKind::Sub);
    b.block(main, {call(outer)});
    b.block(outer, {sound(1), call(s), sound(2), call(s), loopset(I(3))}, Jump{1});
    b.block(outer, {}, LoopTest{0, 2, 3});
    b.block(outer, {call(s)}, Jump{1});
    b.block(outer, {call(s), sound(3), call(s)});
    b.fn(outer).repeats.push_back(Repeat{0, 1, false, true});
    b.block(s, {set(t, V(x)), loopset(I(2))}, Jump{1});
    b.block(s, {}, LoopTest{0, 2, 3});
    b.block(s, {add(t, I(1))}, Jump{1});
    b.block(s, {set(x, V(t))}, Branch{Cmp::GT, V(x), I(3), 4, 5});
    b.block(s, {sound(4)});
    b.block(s, {});
    b.fn(s).repeats.push_back(Repeat{0, 1, false, true});
  };
  Builder one_by_one, at_once;
  FuncId outer = -1;
  build(one_by_one, outer);
  build(at_once, outer);
  for (bool found = true; found;) {
    found = false;
    const Function& f = one_by_one.fn(outer);
    for (std::size_t blk = 0; blk < f.blocks.size() && !found; ++blk)
      for (std::size_t i = 0; i < f.blocks[blk].instrs.size() && !found; ++i)
        if (callee_of(f.blocks[blk].instrs[i]) >= 0) {
          inline_call(one_by_one.p, outer, static_cast<BlockId>(blk), i);
          found = true;
        }
  }
  Diagnostics d;
  Log log;
  ASSERT_TRUE(resolve_calls(at_once.p, OptLevel::O0, d, log));
  EXPECT_EQ(count_ops(at_once.fn(outer), rcx::Op::CallSubroutine), 0u);
  EXPECT_EQ(to_string(at_once.p, at_once.fn(outer)), to_string(one_by_one.p, one_by_one.fn(outer)));
  EXPECT_EQ(at_once.p.vars.size(), one_by_one.p.vars.size());
  auto loops = [](const Function& f) {
    std::vector<std::pair<BlockId, BlockId>> out;
    for (const auto& r : f.repeats) out.emplace_back(r.setup, r.head);
    return out;
  };
  EXPECT_EQ(loops(at_once.fn(outer)), loops(one_by_one.fn(outer)));
  EXPECT_EQ(loops(at_once.fn(outer)).size(), 6u);  // its own and five copies'
  // Each loop still names the block ending in its loopset and its test.
  const Function& f = at_once.fn(outer);
  for (const auto& [setup, head] : loops(f)) {
    const Block& s = f.blocks[static_cast<std::size_t>(setup)];
    ASSERT_FALSE(s.instrs.empty()) << "setup " << setup;
    EXPECT_EQ(s.instrs.back().op, rcx::Op::SetLoopCounter) << "setup " << setup;
    EXPECT_TRUE(std::holds_alternative<LoopTest>(f.blocks[static_cast<std::size_t>(head)].term)) << "head " << head;
  }
}

}  // namespace

TEST(Order, CycleComponentsGroupTheBlocksOfEachLoop) {
  // 0 -> 1; 1 -> {2, 4}; 2 -> 3; 3 -> 1 (a loop of 1, 2, 3); 4 -> 5;
  // 5 -> {5, 6} (a poll on itself); 6 ends.
  Builder b;
  VarId g = b.global("g");
  FuncId f = b.function("main");
  b.block(f, {}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(g), I(0), 2, 4});
  b.block(f, {sound(1)}, Jump{3});
  b.block(f, {sound(2)}, Jump{1});
  b.block(f, {sound(3)}, Jump{5});
  b.block(f, {}, Branch{Cmp::EQ, V(g), I(1), 5, 6});
  b.block(f, {});
  std::vector<int> c = cycle_components(b.fn(f));
  ASSERT_EQ(c.size(), 7u);
  EXPECT_EQ(c[1], c[2]);
  EXPECT_EQ(c[2], c[3]);
  for (int other : {0, 4, 5, 6}) EXPECT_NE(c[static_cast<std::size_t>(other)], c[1]);
  EXPECT_NE(c[0], c[4]);
  EXPECT_NE(c[4], c[5]);
  EXPECT_NE(c[5], c[6]);
}

TEST(Complements, SetNegateAndDecrementBecomeASubtractionFromMinusOne) {
  // ~x computed into t: set t, x; mul t, -1; sub t, 1  ->  set t, -1; sub t, x.
  Builder b;
  VarId x = b.global("x"), t = b.temp();
  FuncId f = b.function("main");
  b.block(f, {set(t, V(x)), mul(t, I(-1)), sub(t, I(1))});
  shorten_complements(b.fn(f), b.p.vars, true);
  const auto& code = b.at(f, 0).instrs;
  ASSERT_EQ(code.size(), 2u);
  EXPECT_EQ(code[0].op, rcx::Op::SetVariable);
  EXPECT_EQ(code[0].args[1], I(-1));
  EXPECT_EQ(code[1].op, rcx::Op::SubtractFromVariable);
  EXPECT_EQ(code[1].args[1], V(x));
}

TEST(Complements, NotInAGlobalAnotherTaskMayRead) {
  // c = -37; c = c * -1; c-- into a global: with another task running it
  // would see c = -1, a value the source never gives c (seed 400225 of the
  // watched-values test at a wider offset). With one task it is shortened.
  for (bool other_tasks : {true, false}) {
    Builder b;
    VarId c = b.global("c");
    FuncId f = b.function("main");
    b.block(f, {set(c, I(-37)), mul(c, I(-1)), sub(c, I(1))});
    shorten_complements(b.fn(f), b.p.vars, other_tasks);
    const auto& code = b.at(f, 0).instrs;
    EXPECT_EQ(code.size(), other_tasks ? 3u : 2u);
    EXPECT_EQ(code[0].args[1], I(other_tasks ? -37 : -1));
  }
}
