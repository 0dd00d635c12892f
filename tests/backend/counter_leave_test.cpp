// A jump out of `repeat` loops that leaves their counters pushed where no
// loop test reads them again (ir/repeat.cpp): the firmware's counters kept,
// as nqc's code keeps them, where a variable count costs a set, a test and
// a subtraction per loop. Sizes and executed instructions worked out by
// hand from the listing; values from what the program means.
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

const char* kGotoOut = R"(
int x, y;
task main() {
  repeat (3) { repeat (5) { x++; if (x == 7) goto done; } y++; }
done:
  y += 10;
}
)";

TEST(CounterLeave, AGotoOutOfNestedRepeatsKeepsTheirCounters) {
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(kGotoOut, level);
    ASSERT_TRUE(c.out);
    EXPECT_TRUE(test::logged(c.log, "leaves its counter pushed"));
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "x"), 7);
    EXPECT_EQ(test::global_value(m, c.out->image, "y"), 11);
    if (level != ir::OptLevel::O2) continue;
    // pwr, dir (6 bytes); loopset 3, loopdec; loopset 5, loopdec (10);
    // x += 1, the test of x, the jump back (14); y += 1 and the jump back
    // (7); y += 10 (5): 42 bytes.
    EXPECT_EQ(c.out->code_bytes, 42);
    // pwr, dir, loopset 3 (3); the first outer pass: loopdec, loopset 5,
    // five inner passes of loopdec, add, test, jump (20), the loopdec that
    // ends the inner loop, y += 1, the jump (25); the second: loopdec,
    // loopset 5, one full inner pass (4) and x reaching 7 (loopdec, add,
    // test: 3) (9); y += 10 (1): 38.
    EXPECT_EQ(m.instructions_executed(), 38);
  }
}

// The jump out comes round again inside an endless loop: each pass would
// leave one more counter, so the repeat counts in a variable.
TEST(CounterLeave, AJumpOutThatComesRoundAgainCountsInAVariable) {
  auto c = test::compile_program(R"(
int x, y;
task main() {
  while (true) {
    repeat (3) { x++; if (x % 2 == 0) break; }
    y++;
    if (y > 8) break;
  }
}
)",
                                 ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  EXPECT_FALSE(test::logged(c.log, "leaves its counter pushed"));
  EXPECT_FALSE(test::logged(c.log, "firmware loop counter"));
  auto m = test::run_image(c.out->image, 1000);
  EXPECT_EQ(test::global_value(m, c.out->image, "y"), 9);
  EXPECT_EQ(test::global_value(m, c.out->image, "x"), 18);
}

// Two counters left below loops nested two deep fill the four; nested
// three deep they would not fit, and the loops left count in variables.
TEST(CounterLeave, CountersLeftCountTowardsTheFour) {
  auto program = [](const std::string& after) {
    return "int x, y, z;\ntask main() {\n  repeat (2) { y++; repeat (3) { x++; if (x == 4) goto out; } }\nout:\n" +
           after + "\n  y += 100;\n}\n";
  };
  auto fits = test::compile_program(program("repeat (2) { y++; repeat (2) { z++; } }"), ir::OptLevel::O2);
  auto deep = test::compile_program(program("repeat (2) { y++; repeat (2) { y++; repeat (2) { z++; } } }"),
                                    ir::OptLevel::O2);
  ASSERT_TRUE(fits.out && deep.out);
  EXPECT_TRUE(test::logged(fits.log, "leaves its counter pushed"));
  EXPECT_FALSE(test::logged(deep.log, "leaves its counter pushed"));
  auto m = test::run_image(fits.out->image, 1000);
  EXPECT_EQ(test::global_value(m, fits.out->image, "y"), 1 + 1 + 2 + 100);
  EXPECT_EQ(test::global_value(m, fits.out->image, "z"), 4);
  auto n = test::run_image(deep.out->image, 1000);
  EXPECT_EQ(test::global_value(n, deep.out->image, "y"), 1 + 1 + 2 + 4 + 100);
  EXPECT_EQ(test::global_value(n, deep.out->image, "z"), 8);
}

// A task another task starts may run again from its start: counters a
// run left would still be there, so its loops count in variables.
TEST(CounterLeave, ATaskStartedByAnotherCountsInAVariable) {
  auto c = test::compile_program(R"(
int x, y;
task helper() { repeat (5) { x++; if (x == 3) break; } y++; }
task main() { start helper; Wait(10); start helper; Wait(10); }
)",
                                 ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  EXPECT_FALSE(test::logged(c.log, "leaves its counter pushed"));
  auto m = test::run_image(c.out->image, 1000);
  EXPECT_EQ(test::global_value(m, c.out->image, "y"), 2);
}

}  // namespace
}  // namespace rcxc
