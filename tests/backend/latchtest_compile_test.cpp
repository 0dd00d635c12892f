// Shapes where -O2's code ran more instructions a loop pass or took more
// bytes than nqc's, counted in the emulator or against `nqc -Trcx -L` of
// the same program: a loop's jump back to its test (ir/latchtest.cpp), a
// local copied from a sensor for one test (ir/negtest.cpp), a power outside
// a byte (ir/lower.cpp).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

std::int64_t instructions_run(const rcx::Image& image, std::int64_t ms) {
  return test::run_image(image, ms).instructions_executed();
}

TEST(LatchTestCompile, AWhileEndingAnOuterLoopsBodyRunsItsBodyAndTestAPass) {
  // The inner loop's way out is the outer loop's top, not the next block,
  // so it is not rotated (that would put a jump on the way in). Its pass
  // was `chk; add; jmp` (3); with the test copied into the latch it is
  // `add; chk` (2), as nqc's `sumv; chkl`. Counted: pwr, dir (2); each of
  // the first two rounds `m += 1`, its test, `n = 0` (3), the test into
  // the loop (1), 50 passes of `add; chk` (100, the last test failing) and
  // the jump back to the top (1); the third stops at StopAllTasks after
  // `m += 1` and its test (3). 2 + 2 * 105 + 3 = 215 (313 with the jump a
  // pass). nqc's code runs a jump into the loop's test each round: 217.
  // (`1 + m`, which nqc computes through a temporary, leaves the bytes the
  // copy takes: 45 against nqc's 61.)
  auto c = test::compile_program(
      "int n, m;\ntask main() {\n  while (true) {\n    m = 1 + m;\n    if (m == 3) StopAllTasks();\n    n = 0;\n"
      "    while (n < 50) n = 1 + n;\n  }\n}\n",
      ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  EXPECT_TRUE(test::logged(c.log, "runs a copy of the test"));
  EXPECT_EQ(instructions_run(c.out->image, 2000), 215);
  EXPECT_EQ(c.out->code_bytes, 45);
}

TEST(LatchTestCompile, ALocalCopiedFromASensorForOneTestIsNotSet) {
  // `int v = SENSOR_1; if (v == 0) n += 1;` ten times, the touch sensor
  // released (0): the test reads the sensor where the copy did. pwr, dir,
  // senstype and the jump into the loop's test (4), ten passes of the
  // loop's test, the test of v and `n += 1` (30; 40 with the copy), the
  // test that leaves (1).
  auto c = test::compile_program(
      "int n;\ntask main() {\n  SetSensor(SENSOR_1, SENSOR_TOUCH);\n  while (n < 10) {\n    int v = SENSOR_1;\n"
      "    if (v == 0) n += 1;\n  }\n}\n",
      ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  EXPECT_EQ(instructions_run(c.out->image, 1000), 4 + 10 * 3 + 1);
}

TEST(LatchTestCompile, APowerOutsideAByteIsItsLowByteAsInNqcsCode) {
  // nqc's `pwr A, 255` (4 bytes) after the 6 of the startup code and `pwr
  // A, 3` (4): 14. Through a temporary it was 19 at -O1. The brick ignores
  // it (the power stays 3), and -O2 leaves it out.
  const std::string text = "task main() {\n  SetPower(OUT_A, 3);\n  SetPower(OUT_A, -1);\n}\n";
  for (auto [level, bytes] : {std::pair{ir::OptLevel::O1, 14}, std::pair{ir::OptLevel::O2, 10}}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    EXPECT_EQ(c.out->code_bytes, bytes);
    auto m = test::run_image(c.out->image, 100);
    EXPECT_EQ(m.state().outputs[0].power, 3);
  }
}

}  // namespace
}  // namespace rcxc
