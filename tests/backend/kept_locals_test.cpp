// Locals read before they are written keep what the last call left, and
// every optimisation level agrees on it (docs/language.md, inline function
// parameters; docs/compiler.md, Variables).
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

constexpr ir::OptLevel kLevels[] = {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os};

// Runs `text` at every level and checks what `first` and `second` end as.
void expect_first_and_second_at_every_level(const std::string& text, int first, int second) {
  for (auto level : kLevels) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1'000);
    EXPECT_EQ(test::global_value(m, c.out->image, "first"), first) << "level " << static_cast<int>(level);
    EXPECT_EQ(test::global_value(m, c.out->image, "second"), second) << "level " << static_cast<int>(level);
  }
}

TEST(KeptLocals, AnInlineFunctionsLocalIsOneVariablePerTaskAtEveryLevel) {
  // As nqc allocates it: main's calls add 0 then 1, t2's 0 then 10. One
  // variable for both tasks would give 13.
  const std::string text = R"(
int a, b;
void f(int x) { int m; a = a + m; m = x; }
task main() { start t2; f(1); Wait(50); f(2); Wait(50); b = 1; }
task t2() { Wait(20); f(10); Wait(50); f(20); }
)";
  for (auto level : kLevels) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 2'000);
    EXPECT_EQ(test::global_value(m, c.out->image, "a"), 11) << "level " << static_cast<int>(level);
    EXPECT_EQ(test::global_value(m, c.out->image, "b"), 1);
  }
}

TEST(KeptLocals, ASubroutinesLocalKeepsItsValueWhenTheSubroutineIsInlined) {
  const std::string text = R"(
int seen, first, second;
sub count_up() { int k; seen = k; k = seen + 10; }
task main() { count_up(); count_up(); first = seen; count_up(); second = seen; }
)";
  expect_first_and_second_at_every_level(text, 10, 20);
}

TEST(KeptLocals, ALocalKeptAcrossCallsFromASubAndATaskIsOneVariableAtEveryLevel) {
  // count_up is inlined into twice (a subroutine cannot call another), then
  // at -O2 and -Os at main's call too (not larger): the copy made last,
  // when no call of count_up is left, keeps k like the first.
  const std::string text = R"(
int seen, first, second;
sub count_up() { int k; seen = k; k = seen + 10; }
sub twice() { count_up(); Wait(1); }
task main() { count_up(); first = seen; twice(); second = seen; }
)";
  expect_first_and_second_at_every_level(text, 0, 10);
}

}  // namespace
}  // namespace rcxc
