// Coin tosses on the loop counter (ir/coin.cpp) in compiled programs: the
// bytes they save, and that the program draws and decides exactly as -O1's
// set-and-test code does, for many seeds and at every counter depth.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/support/compiled.h"

using namespace rcxc;
using test::compile_program;

namespace {

const std::vector<std::uint8_t> kLoopsetRandom1 = {0x82, 0x04, 0x01};

bool has_toss(const rcx::Image& image) {
  for (const auto& f : image.fragments)
    if (std::search(f.code.begin(), f.code.end(), kLoopsetRandom1.begin(), kLoopsetRandom1.end()) != f.code.end())
      return true;
  return false;
}

// -Os against -O1 for seeds 1..20, and whether -Os tossed a coin.
void expect_same_as_o1(const std::string& src, bool tossed) {
  auto os = test::expect_same_as_o1(src, 20);
  ASSERT_TRUE(os.out);
  EXPECT_EQ(has_toss(os.out->image), tossed);
}

}  // namespace

TEST(CoinCompile, TheTutorialsTurnSavesFiveBytesAndAVariable) {
  // 04_if's loop: a set (5) and a test (7) become loopset (3) and two
  // loop tests (2 + 2).
  const std::string src = R"(
    task main() {
      while (true) {
        OnFwd(OUT_A+OUT_C); Wait(100);
        if (Random(1) == 0) { OnRev(OUT_C); } else { OnRev(OUT_A); }
        Wait(85);
      }
    })";
  auto os = compile_program(src);
  auto o1 = compile_program(src, ir::OptLevel::O1);
  ASSERT_TRUE(os.out && o1.out);
  EXPECT_TRUE(has_toss(os.out->image));
  EXPECT_EQ(os.out->slots_used, 0);
  EXPECT_EQ(o1.out->slots_used, 1);
  // Counted by hand: startup 6, dir and on 4, wait 4, toss 7, the two
  // sides 2 + 2 and a jump 2, wait 4, jump back 2.
  EXPECT_EQ(os.out->code_bytes, 33);
  EXPECT_FALSE(has_toss(o1.out->image));
  expect_same_as_o1(src, true);
}

TEST(CoinCompile, EveryToss3CountersDeepDecidesAsTheVariableDoes) {
  // Each toss's face goes to the datalog, so the sequences must agree
  // draw by draw; the loops around must still count 2 x 3 x 2 times.
  expect_same_as_o1(R"(
    int heads, tails, n;
    task main() {
      CreateDatalog(20);
      repeat (2) { n += 100; repeat (3) { n += 10; repeat (2) {
        n += 1;
        if (Random(1) != 0) { heads++; AddToDatalog(1); } else { tails++; AddToDatalog(0); }
      } } }
    })",
                    true);
}

TEST(CoinCompile, FourCountersDeepTheVariableStays) {
  // A fifth loopset would overwrite the innermost count.
  expect_same_as_o1(R"(
    int heads, tails, n;
    task main() {
      repeat (2) { n += 1000; repeat (2) { n += 100; repeat (2) { n += 10; repeat (2) {
        if (Random(1) == 0) heads++; else tails++;
        n += 1;
      } } } }
    })",
                    false);
}

TEST(CoinCompile, ASubroutineCalledInAndOutsideALoop) {
  // The subroutine runs on its caller's counter stack: one deep, then none.
  // (Two tasks tossing at once would not do here: the toss takes one
  // instruction longer on one side, which can reorder the tasks' draws.)
  expect_same_as_o1(R"(
    int a;
    sub flip() { if (Random(1) == 1) PlaySound(1); else PlaySound(2); }
    task main() { repeat (5) { flip(); a++; Wait(20); } flip(); Wait(200); }
    )",
                    true);
}
