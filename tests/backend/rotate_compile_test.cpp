// Loop rotation (ir/rotate.cpp) on whole programs, counted in the emulator:
// the instructions a run executes, against counts made by hand from the
// instructions each path runs, and nqc's from `nqc -Trcx -L` of the same
// program.
#include <gtest/gtest.h>

#include <cstdint>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

TEST(RotateCompile, AWhileFirstInAnEndlessLoopRunsNoJumpAPass) {
  // Both loops go back to the inner test. Rotated, the inner pass is
  // `add; chk` (2) where it was `chk; add; jmp` (3), as nqc's code is.
  // rcxc's code: pwr, dir, the jump in to the test (3); the first round
  // 50 passes (100), the test that leaves (1), `m += 1`, its test, `n = 0`,
  // the jump back (4); the second round 100 + 1, `m += 1`, its test and
  // the stop (3): 212 (311 unrotated). nqc's: the same, but its outer
  // latch jumps to its jump in to the test, one more: 213.
  auto c = test::compile_program(
      "int n, m;\ntask main() {\n  while (true) {\n    while (n < 50) n += 1;\n    m += 1;\n"
      "    if (m == 2) StopAllTasks();\n    n = 0;\n  }\n}\n",
      ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  rcx::Machine m = test::run_image(c.out->image, 2000);
  EXPECT_EQ(test::global_value(m, c.out->image, "m"), 2);
  EXPECT_EQ(m.instructions_executed(), 212);
}

}  // namespace
}  // namespace rcxc
