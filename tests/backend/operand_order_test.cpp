// `c + e`, `c * e`, `c & e`, `c | e` with c a constant or variable and e
// something the arithmetic opcodes cannot take (a sensor, a timer, a
// random number, an expression): e is computed first, into the target,
// and c applied to it (ir/lower.cpp, right_first). Values worked out by
// hand; sizes counted by hand from the instructions each statement needs.
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

constexpr int kStartup = 6;  // pwr ABC, 7 and dir ABC, fwd
constexpr int kSet = 5, kArith = 5, kWait = 4;

int code_bytes(const std::string& text, ir::OptLevel level) {
  auto c = test::compile_program(text, level);
  EXPECT_TRUE(c.out) << text;
  return c.out ? c.out->code_bytes : -1;
}

TEST(OperandOrder, AConstantPlusASourceTakesTwoInstructions) {
  // set w, random(300); add w, 300 (left to right: set, set into a second
  // temporary, add).
  EXPECT_EQ(code_bytes("int w; task main() { w = 300 + Random(300); }", ir::OptLevel::O1),
            kStartup + kSet + kArith);
  EXPECT_EQ(code_bytes("int y; task main() { y = 5 + Timer(0); }", ir::OptLevel::O1), kStartup + kSet + kArith);
  // A wait's temporary likewise: set t, random(5); mul t, 10; add t, 20;
  // wait t.
  EXPECT_EQ(code_bytes("task main() { Wait(20 + 10 * Random(5)); }", ir::OptLevel::O1),
            kStartup + kSet + 2 * kArith + kWait);
}

TEST(OperandOrder, ValuesAreThoseOfLeftToRight) {
  const char* text = R"(
int x, y, w, v, p, k, u;
task main() {
  x = 7;
  y = 5 + Timer(0);
  w = 300 + Random(300);
  v = 20 + 10 * Random(5);
  p = x * (Timer(0) + 2);
  k = 3; k = 2 * (k += 5);
  u = x + (x = 4);
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    auto at = [&](const char* name) { return test::global_value(m, c.out->image, name); };
    EXPECT_EQ(at("y"), 5);  // timer 0 reads 0 in its first 100 ms
    EXPECT_GE(at("w"), 300);
    EXPECT_LE(at("w"), 600);
    EXPECT_GE(at("v"), 20);
    EXPECT_LE(at("v"), 70);
    EXPECT_EQ(at("v") % 10, 0);
    EXPECT_EQ(at("p"), 14);
    EXPECT_EQ(at("k"), 16);  // k += 5 first (the constant cannot change), then doubled
    // x's old value is read before the assignment on the right changes
    // it: the right side has an effect, so the order stays.
    EXPECT_EQ(at("u"), 11);
    EXPECT_EQ(at("x"), 4);
  }
}

TEST(OperandOrder, ATestOnTheRightStaysSecond) {
  // c + (b < c) * 3 keeps computing the truth in a temporary, where the
  // branches take its constants (joinconst.cpp): p = c; p += 3 on the
  // side where b < c.
  const char* text = "int b, c, p; task main() { b = 2; c = 5; p = c + (b < c) * 3; }";
  auto c = test::compile_program(text, ir::OptLevel::O2);
  ASSERT_TRUE(c.out);
  auto m = test::run_image(c.out->image, 1000);
  EXPECT_EQ(test::global_value(m, c.out->image, "p"), 8);
  // b = 2, c = 5, p = c, the test (7 bytes), p += 3.
  EXPECT_EQ(c.out->code_bytes, kStartup + 3 * kSet + 7 + kArith);
}

}  // namespace
}  // namespace rcxc
