// A loop's jump back to its test runs a copy of the test (ir/latchtest.cpp).
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

// while (true) { PlaySound(1); while (x cmp y) PlaySound(2); }: block 0 the
// outer body, falling into 1, the inner test (to 2 when it holds, back to
// 0 when not), and 2 the inner body, whose jump back to 1 is the latch.
struct Nested {
  Builder b;
  VarId x = b.global("x"), y = b.global("y");
  FuncId f = b.function("main");
  explicit Nested(Cmp cmp = Cmp::EQ, Operand right = I(0), std::vector<Instr> test_code = {}) {
    b.block(f, {sound(1)}, Jump{1});
    b.block(f, std::move(test_code), Branch{cmp, V(x), right, 2, 0});
    b.block(f, {sound(2)}, Jump{1});
  }
  // What the pass spent; its log in `log`.
  int run(int bytes_to_spend = 100) { return copy_tests_into_latches(b.fn(f), log, bytes_to_spend); }
  Log log;
};

}  // namespace

TEST(LatchTest, AnInnerLoopsLatchBranchesBackToItsBody) {
  Nested n;
  // The test (7) and a jump to the outer loop (2), for the jump to the test.
  EXPECT_EQ(n.run(), 7);
  EXPECT_EQ(n.log.size(), 1u);
  const auto* br = std::get_if<Branch>(&n.b.at(n.f, 2).term);
  ASSERT_NE(br, nullptr);
  EXPECT_EQ(br->cmp, Cmp::EQ);
  EXPECT_EQ(br->then, 2);  // itself: `PlaySound(2); test` a pass
  EXPECT_EQ(br->otherwise, 0);
  // The test stays for the way in.
  EXPECT_TRUE(std::holds_alternative<Branch>(n.b.at(n.f, 1).term));
}

TEST(LatchTest, TheBodyIsTheSideTheCopyBranchesTo) {
  // An `until (x != y);` at the outer body's end: the test goes back to
  // the outer loop when x != y, else to an empty block that jumps back to
  // it. The copy polls in place, branching to itself while x == y.
  Builder b;
  VarId x = b.global("x"), y = b.global("y");
  FuncId f = b.function("main");
  b.block(f, {sound(1)}, Jump{1});
  b.block(f, {}, Branch{Cmp::NE, V(x), V(y), 0, 2});
  b.block(f, {}, Jump{1});
  Log log;
  EXPECT_EQ(copy_tests_into_latches(b.fn(f), log, 100), 7);
  const auto& br = std::get<Branch>(b.at(f, 2).term);
  EXPECT_EQ(br.cmp, Cmp::EQ);
  EXPECT_EQ(br.then, 2);
  EXPECT_EQ(br.otherwise, 0);
}

TEST(LatchTest, NothingWithoutTheBytesOrAOneInstructionBranchBack) {
  Nested poor;
  EXPECT_EQ(poor.run(6), 0);
  EXPECT_TRUE(std::holds_alternative<Jump>(poor.b.at(poor.f, 2).term));
  // x < y of two variables has no single test that branches when it
  // holds: the copy's pass would be a test and a jump, as before.
  Nested strict(Cmp::LT, V(1));
  EXPECT_EQ(strict.run(), 0);
  // A test with code of its own is not a test alone.
  Nested busy(Cmp::EQ, I(0), {sound(3)});
  EXPECT_EQ(busy.run(), 0);
}

TEST(LatchTest, AWayOutThatFollowsTakesNoJump) {
  // do { PlaySound(1); } while (x == 0); PlaySound(3); with the test first
  // in the layout: the latch (block 1) jumps back to it, and the way out
  // (block 2) follows the latch.
  Builder b;
  VarId x = b.global("x");
  FuncId f = b.function("main");
  b.block(f, {}, Branch{Cmp::EQ, V(x), I(0), 1, 2});
  b.block(f, {sound(1)}, Jump{0});
  b.block(f, {sound(3)});
  Log log;
  EXPECT_EQ(copy_tests_into_latches(b.fn(f), log, 100), 5);
}
