// Cross-jumping (ir/cfg.cpp, share_tails) on whole programs: an early exit
// that is nothing but the end its function has anyway branches to that
// end. Sizes counted by hand from the instructions.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

// An inline function whose early return switches off what its end
// switches off too, called in an endless loop.
constexpr char kEarlyExitLikeTheEnd[] =
    "int level, best;\n"
    "void steer() {\n"
    "  if (best <= level) { Off(OUT_A+OUT_C); return; }\n"
    "  Wait(best);\n"
    "  Off(OUT_A+OUT_C);\n"
    "}\n"
    "task main() {\n"
    "  while (true) {\n"
    "    level = SENSOR_1;\n"
    "    best = SENSOR_2;\n"
    "    OnFwd(OUT_A+OUT_C);\n"
    "    steer();\n"
    "  }\n"
    "}\n";

TEST(SharedTailCompile, AnEarlyExitBranchesToTheEndItRepeats) {
  // pwr ABC, 7; dir ABC, fwd (6), two sets of a sensor (10), out AC, on
  // (2), chk best <= level (7), wait best (4), out AC, off (2), jmp (2):
  // 33 bytes at both levels. The exit kept its own out AC, off and jump
  // back, with a jump over them: 37. nqc's code is 41.
  for (auto level : {ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(kEarlyExitLikeTheEnd, level);
    ASSERT_TRUE(c.out);
    EXPECT_EQ(c.out->code_bytes, 33);
  }
}

}  // namespace
}  // namespace rcxc
