// Loops entered past a known test (ir/entrytest.cpp) on whole programs,
// counted in the emulator.
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

TEST(EntryTestCompile, ALoopThatNeverRunsTakesTheSetThatSkipsItAlong) {
  // `int k = 20; while (k < 10)` fails on the way in: the loop goes, and
  // with it the only read of k, so `k = 20` goes too. What runs: the
  // startup's power and direction, then the output off (3, and 2 bytes
  // for the off after the startup's 6). Before, `set k, 20` stayed (4).
  auto c = test::compile_program(
      "task main() {\n  int k = 20;\n  while (k < 10) { PlaySound(2); k++; }\n  Off(OUT_A);\n}\n",
      ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  rcx::Machine m = test::run_image(c.out->image, 1000);
  EXPECT_EQ(m.instructions_executed(), 3);
  EXPECT_EQ(c.out->image.fragments.at(0).code.size(), 8u);
}

TEST(EntryTestCompile, AValueReadAfterTheSkippedLoopIsKept) {
  // k is read after the loop: its set stays.
  auto c = test::compile_program(
      "int g;\ntask main() {\n  int k = 20;\n  while (k < 10) { PlaySound(2); k++; }\n  g = k;\n}\n",
      ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  rcx::Machine m = test::run_image(c.out->image, 1000);
  EXPECT_EQ(test::global_value(m, c.out->image, "g"), 20);
}

}  // namespace
}  // namespace rcxc
