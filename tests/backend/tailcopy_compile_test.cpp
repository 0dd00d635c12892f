// Short joins copied into loop sides (ir/tailcopy.cpp) on whole programs:
// the copies never make -O2's code larger than the function as lowered.
// Sizes counted by hand from the instructions, and checked against nqc's
// listing (nqc -Trcx -L) of the same programs.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

constexpr char kCopyLogged[] = "a jump in a loop to a short block runs a copy";

// `text` compiled at -O2, where the copies are made.
test::Compiled at_o2(const std::string& text) {
  auto c = test::compile_program(text, ir::OptLevel::O2);
  EXPECT_TRUE(c.out) << text;
  return c;
}

TEST(TailCopyCompile, ALoopNothingElseShortensGetsNoCopy) {
  // pwr ABC, 7; dir ABC, fwd (6), chk (7), set (5), jmp (2), set (5), pwr
  // AC, var (4), jmp (2): 31 bytes, nqc's too. The power command's copy
  // on the side that jumped to it made it 35.
  auto c = at_o2(
      "int g;\ntask main() {\n  while (true) {\n    if (g == 1) g = 4; else g = 6;\n"
      "    SetPower(OUT_A+OUT_C, g);\n  }\n}\n");
  ASSERT_TRUE(c.out);
  EXPECT_EQ(c.out->code_bytes, 31);
  EXPECT_FALSE(test::logged(c.log, kCopyLogged));
}

TEST(TailCopyCompile, AJoinOfEightSidesIsNotCopiedSevenTimes) {
  // nqc's code is 117 bytes: seven tests, eight assignments, seven jumps
  // to the join, SetPower and Fwd, the jump back. Each side got its own
  // copy of the join (144 bytes).
  std::string text = "int g;\ntask main() {\n  while (true) {\n";
  for (int k = 1; k <= 7; ++k)
    text += std::string(k == 1 ? "    if" : "    else if") + " (g == " + std::to_string(k) + ") g = " +
            std::to_string(k % 7 + 1) + ";\n";
  text += "    else g = 6;\n    SetPower(OUT_A+OUT_C, g); Fwd(OUT_A+OUT_C);\n  }\n}\n";
  auto c = at_o2(text);
  ASSERT_TRUE(c.out);
  EXPECT_LE(c.out->code_bytes, 117);
}

TEST(TailCopyCompile, WhereOtherPassesSavedBytesTheCopyStays) {
  // The other passes take this loop from 68 bytes as lowered (nqc's 68)
  // to 61: the copy of `n++` (5 bytes) fits in what they saved.
  auto c = at_o2(
      "int a, b, n;\ntask main() {\n  repeat (10) {\n    if (n % 3 == 0) { a += 2; Off(OUT_B); } "
      "else { b += 3; OnFwd(OUT_B); }\n    n++;\n  }\n}\n");
  ASSERT_TRUE(c.out);
  EXPECT_TRUE(test::logged(c.log, kCopyLogged));
}

}  // namespace
}  // namespace rcxc
