// Computing into the assigned variable (ir/coalesce.cpp) on whole programs:
// the values nqc's semantics give, worked out by hand, at every level, and
// fewer bytes from -O2 than at -O1, where the temporaries are copied.
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

const char* kAssignments = R"(
int a, b, y, z, g, h, x;
task main() {
  a = 3; b = 5; y = 10; z = 4; g = -7; x = 20;
  b = a * b;
  z = y - z;
  g = g % 4;
  h = (x + 1) % 6;
  x = 100 - x;
}
)";

TEST(Coalesce, AssignmentsThatReadTheirTargetComputeInPlace) {
  int o1_bytes = 0;
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(kAssignments, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "b"), 15);
    EXPECT_EQ(test::global_value(m, c.out->image, "z"), 6);
    EXPECT_EQ(test::global_value(m, c.out->image, "g"), -3);  // truncating, as the firmware divides
    EXPECT_EQ(test::global_value(m, c.out->image, "h"), 3);
    EXPECT_EQ(test::global_value(m, c.out->image, "x"), 80);
    if (level == ir::OptLevel::O1) o1_bytes = c.out->code_bytes;
    // b = a * b: one multiply of b (5 bytes) instead of set, multiply, copy;
    // z = y - z two instructions instead of three; g % 4 ends with one
    // subtraction from g instead of a subtraction, a negation and a copy;
    // x = 100 - x two instead of three. 30 bytes in all (h, which its
    // right side does not read, is computed in place at every level).
    if (level == ir::OptLevel::O2) {
      EXPECT_EQ(c.out->code_bytes, o1_bytes - 30);
    }
  }
}

// `V = V - (X + Y)` and the like subtract (or add) X and Y from V one
// after the other instead of summing them in a temporary first; Y may not
// be V (it changes first), X may.
TEST(Coalesce, ASumAddedToItsTargetIsAddedTermByTerm) {
  const char* text = R"(
int a, b, c, d, e, x;
task main() {
  // Timer(0) is 0 so early, but not known to the optimiser.
  x = Timer(0) + 7;
  a = Timer(0) + 100; b = a; c = a; d = a; e = a;
  a = a - (x + 5);
  b = b + (x - 5);
  c = c - (x - 5 + x);
  d = d - (d + x);
  e = e - (x + e);
}
)";
  int o1_bytes = 0;
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "a"), 88);
    EXPECT_EQ(test::global_value(m, c.out->image, "b"), 102);
    EXPECT_EQ(test::global_value(m, c.out->image, "c"), 91);
    EXPECT_EQ(test::global_value(m, c.out->image, "d"), -7);
    EXPECT_EQ(test::global_value(m, c.out->image, "e"), -7);
    if (level == ir::OptLevel::O1) o1_bytes = c.out->code_bytes;
    // Each loses the set of the temporary the sum was made in (5 bytes).
    // d and e, whose right sides read them after the sum, are still
    // computed in a temporary copied into them at the end.
    if (level == ir::OptLevel::O2) {
      EXPECT_EQ(c.out->code_bytes, o1_bytes - 25);
    }
  }
}

// With another task running, a global is computed in steps only where
// each step is a value the source gives it: `v = x - v` as `v -= x; v *=
// -1` held v - x (negative here) for an instruction, and a task waiting for
// v < 0 switched output B on 100 ms early, where nqc's code waits for the
// real negative value at 200 ms.
TEST(Coalesce, AnotherTaskNeverSeesAStepOfAGlobalsComputation) {
  const char* text = R"(
int v, x;
task watch() { until (v < 0); OnFwd(OUT_B); }
task main() {
  v = Timer(0) + 10;  // 0 so early, but not known to the optimiser
  start watch;
  x = Timer(0) + 30;
  Wait(10);
  v = x - v;
  Wait(10);
  v = v + (x - 50);
  Wait(10);
  v = v - (x + 5);
  Wait(10);
}
)";
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto early = test::run_image(c.out->image, 290);
    EXPECT_NE(early.state().outputs[1].mode, rcx::OutputMode::On) << static_cast<int>(level);
    auto late = test::run_image(c.out->image, 400);
    EXPECT_EQ(test::global_value(late, c.out->image, "v"), -35);
    EXPECT_EQ(late.state().outputs[1].mode, rcx::OutputMode::On);
  }
}

// `d = (v != 0)` as `d = abs(v); d = sign(d)` held |v| (5) in d for an
// instruction, and a task waiting for d > 1 switched output B on, where
// nqc's code (d = 0, then 1) never does. With a second task running, a
// global keeps the test.
TEST(NonZeroCompile, AnotherTaskNeverSeesTheAbsoluteValue) {
  const char* text = R"(
int d, v;
task watch() { until (d > 1); OnFwd(OUT_B); }
task main() {
  start watch;
  v = Timer(0) + 5;  // 0 so early, but not known to the optimiser
  Wait(10);
  d = (v != 0);
  Wait(10);
}
)";
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 500);
    EXPECT_EQ(test::global_value(m, c.out->image, "d"), 1);
    EXPECT_NE(m.state().outputs[1].mode, rcx::OutputMode::On) << static_cast<int>(level);
  }
}

// `d >>= 15` as `d &= -32768; d /= -32768` held -32768 in d for an
// instruction when d was negative, and a task waiting for d == -32768
// switched output B on, where nqc's code never does (it shows d & 32767,
// then 0, then 1). With a second task running, a global keeps the test;
// at -Os the same for `d >>= 3` (d & -8 for an instruction).
TEST(ShiftRightCompile, AnotherTaskNeverSeesTheMaskedSign) {
  const char* text = R"(
int d, e;
task watch() { until (d == -32768 || e == -8); OnFwd(OUT_B); }
task main() {
  start watch;
  d = Timer(0) - 7;  // 0 so early, but not known to the optimiser
  e = d;
  Wait(10);
  d >>= 15;
  e >>= 3;
  Wait(10);
}
)";
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 500);
    EXPECT_EQ(test::global_value(m, c.out->image, "d"), 1);
    EXPECT_EQ(test::global_value(m, c.out->image, "e"), 8191);
    EXPECT_NE(m.state().outputs[1].mode, rcx::OutputMode::On) << static_cast<int>(level);
  }
}

// `g = -a` computed in place held a (5) for an instruction, `h = ~(a + 1)`
// held 6 and -6, `k = a ^ 3` held a | 3 (7), `n = ~n` held -n: a task
// waiting for any of
// them switched output B on, where nqc's code (0, then -5; -1, then -7;
// the result) never does. With a second task running, those go as nqc's
// or through a temporary.
TEST(LowerCompile, AnotherTaskNeverSeesStepsNqcsCodeDoesNotShow) {
  const char* text = R"(
int a, g, h, k, n;
task watch() { until (g > 0 || h > 0 || k == 7 || n == -5); OnFwd(OUT_B); }
task main() {
  start watch;
  a = Timer(0) + 5;  // 0 so early, but not known to the optimiser
  Wait(10);
  g = -a;
  h = ~(a + 1);
  k = a ^ 3;
  n = a;
  n = ~n;
  Wait(10);
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 500);
    EXPECT_EQ(test::global_value(m, c.out->image, "g"), -5);
    EXPECT_EQ(test::global_value(m, c.out->image, "h"), -7);
    EXPECT_EQ(test::global_value(m, c.out->image, "k"), 6);
    EXPECT_EQ(test::global_value(m, c.out->image, "n"), -6);
    EXPECT_NE(m.state().outputs[1].mode, rcx::OutputMode::On) << static_cast<int>(level);
  }
}

// The 16-bit edges: a reverse subtraction done as a negation wraps as the
// subtraction does.
TEST(Coalesce, ANegatedSubtractionWrapsLikeTheSubtraction) {
  const char* text = R"(
int y, z, w;
task main() {
  y = -32768; z = 1; w = 32767;
  z = y - z;
  w = -2 - w;
}
)";
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "z"), 32767);
    EXPECT_EQ(test::global_value(m, c.out->image, "w"), 32767);
  }
}

// `a = b - OFFSET - 10`, `c = 2 + b + 5` in a program of one task, and
// `a += 3; a -= 1`: each constant after the first gathered (ir/gather.cpp),
// from -O1. -O0 keeps every step: 6 of startup, 5 for b, 15 + 15 + 10.
TEST(Coalesce, ConstantsInARowAreOneStep) {
  const char* text = R"(
#define OFFSET 100
int a, b, c;
task main() {
  b = Timer(0) + 40;
  a = b - OFFSET - 10;
  c = 2 + b + 5;
  a += 3; a -= 1;
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "a"), -68);
    EXPECT_EQ(test::global_value(m, c.out->image, "c"), 47);
    // Optimised: b's two steps, then a = b; a -= 110; c = b; c += 7; a += 2.
    EXPECT_EQ(c.out->code_bytes, level == ir::OptLevel::O0 ? 6 + 10 + 15 + 15 + 10 : 6 + 10 + 10 + 10 + 5)
        << static_cast<int>(level);
  }
}

}  // namespace
}  // namespace rcxc

namespace rcxc {
namespace {

// `n % 3 != 0` tests the remainder before its negation, for every n
// around the 16-bit edges (the remainder of -32768 % 3 included), and
// consecutive waits are one wait: the count of loop passes and the time
// they take are what -O1's code gives.
TEST(NegatedTest, RemaindersTestedWithoutNegationCountTheSame) {
  const char* text = R"(
int n, hits, misses;
task main() {
  n = -32768; hits = 0; misses = 0;
  repeat (40) {
    if (n % 3 != 0) misses += 1; else hits += 1;
    n += 1;
  }
  n = 32767;
  do { n -= 1; hits += 100; } while (n % 7 != 0);
  Wait(3); Wait(4);
  misses += 1000;
}
)";
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 2000);
    // -32768 .. -32729: multiples of 3 are -32766, -32763, ..., -32730 (13).
    // 32766 .. 32760 counted down to 32760 = 7 * 4680: 7 passes.
    EXPECT_EQ(test::global_value(m, c.out->image, "hits"), 13 + 700);
    EXPECT_EQ(test::global_value(m, c.out->image, "misses"), 27 + 1000);
    if (level != ir::OptLevel::O1) {
      int negations = 0, waits = 0;
      for (const auto& frag : c.out->fragments)
        for (const auto& in : frag.instrs) {
          negations += in.bytes.size() == 5 && in.bytes[0] == rcx::info(rcx::Op::MultiplyVariable).code &&
                       in.bytes[3] == 0xff && in.bytes[4] == 0xff;
          waits += in.bytes[0] == rcx::info(rcx::Op::Wait).code;
        }
      EXPECT_EQ(negations, 0);
      EXPECT_EQ(waits, 1);
    }
  }
}

}  // namespace
}  // namespace rcxc

namespace rcxc {
namespace {

// A comparison's 0 or 1 scaled or complemented (`c + (b < c) * 3`,
// `c + ~(b < c)`): the constants set on each side are the results, at
// every level the same values.
TEST(JoinConstant, ScaledComparisonsComputeTheSame) {
  const char* text = R"(
int b, c, p, q, r, s;
task main() {
  b = 2; c = 5;
  p = c + (b < c) * 3;
  q = c + ~(b < c);
  r = c + (c < b) * 3;
  s = c + ~(c < b);
}
)";
  int o1_bytes = 0;
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "p"), 8);
    EXPECT_EQ(test::global_value(m, c.out->image, "q"), 3);   // ~1 = -2
    EXPECT_EQ(test::global_value(m, c.out->image, "r"), 5);
    EXPECT_EQ(test::global_value(m, c.out->image, "s"), 4);   // ~0 = -1
    if (level == ir::OptLevel::O1) o1_bytes = c.out->code_bytes;
    // Per statement one multiply (or the complement's multiply and
    // subtraction) fewer: 2 * 5 + 2 * 10 bytes; and where one side's
    // constant is then 0 (p, r), the addition is `p += 3` on the other
    // side, without the temporary's two sets: 2 * 10 more.
    if (level == ir::OptLevel::O2) {
      EXPECT_EQ(c.out->code_bytes, o1_bytes - 50);
    }
  }
}

}  // namespace
}  // namespace rcxc

namespace rcxc {
namespace {

// `d = (v != 0)` as abs then sign: 1 for every nonzero v, -32768 (whose
// absolute value the firmware gives as 32767) and -1 included.
TEST(NonZero, NonZeroValuesAreOneAtTheEdges) {
  const char* text = R"(
int v, p, q, r, s;
task main() {
  v = -32768; p = (v != 0);
  v = -1; q = (v != 0);
  v = 0; r = (0 != v);
  v = 32767; s = (v != 0);
}
)";
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "p"), 1);
    EXPECT_EQ(test::global_value(m, c.out->image, "q"), 1);
    EXPECT_EQ(test::global_value(m, c.out->image, "r"), 0);
    EXPECT_EQ(test::global_value(m, c.out->image, "s"), 1);
    int tests = 0;
    for (const auto& frag : c.out->fragments)
      for (const auto& in : frag.instrs) tests += in.bytes[0] == rcx::info(rcx::Op::TestAndBranchNear).code;
    EXPECT_EQ(tests, level == ir::OptLevel::O1 ? 4 : 0);
  }
}

}  // namespace
}  // namespace rcxc

namespace rcxc {
namespace {

// Tests of values computed by one-to-one arithmetic (ir/negtest.cpp)
// count what the 16-bit arithmetic gives, over the whole range in steps of
// 257 and around zero, against counts worked out here on int16_t.
TEST(NegatedTest, TestsThroughOneToOneArithmeticCountTheSame) {
  const char* text = R"(
int n, a, b, c, d, e;
void count() {
  if (n * 3 + 5 == 2) a += 1;
  if (10 - n != 4) b += 1;
  if (~n <= 5) c += 1;
  if (n * 3 == -32768) d += 1;
  if (n + 1 <= 0) e += 1;
}
task main() {
  a = 0; b = 0; c = 0; d = 0; e = 0;
  n = -32768;
  repeat (256) { count(); n += 257; }
  n = -40;
  repeat (81) { count(); n += 1; }
}
)";
  int a = 0, b = 0, c = 0, d = 0, e = 0;
  auto count = [&](int n) {
    auto w = [](long v) { return static_cast<int16_t>(static_cast<uint16_t>(v & 0xffff)); };
    a += w(n * 3L + 5) == 2;
    b += w(10L - n) != 4;
    c += w(-1L - n) <= 5;
    d += w(n * 3L) == -32768;
    e += w(n + 1L) <= 0;
  };
  for (int k = 0; k < 256; ++k) count(-32768 + 257 * k);
  for (int n = -40; n <= 40; ++n) count(n);
  int o1_bytes = 0;
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto comp = test::compile_program(text, level);
    ASSERT_TRUE(comp.out);
    auto m = test::run_image(comp.out->image, 200'000);
    EXPECT_EQ(test::global_value(m, comp.out->image, "a"), a);
    EXPECT_EQ(test::global_value(m, comp.out->image, "b"), b);
    EXPECT_EQ(test::global_value(m, comp.out->image, "c"), c);
    EXPECT_EQ(test::global_value(m, comp.out->image, "d"), d);
    EXPECT_EQ(test::global_value(m, comp.out->image, "e"), e);
    if (level == ir::OptLevel::O1) o1_bytes = comp.out->code_bytes;
    // Four of the five tests compare n itself: their temporary's copy and
    // arithmetic go (15 + 10 + 10 + 10 bytes), in each of the two copies
    // of count() (inlined: called twice).
    if (level == ir::OptLevel::O2) {
      EXPECT_EQ(comp.out->code_bytes, o1_bytes - 90);
    }
  }
}

}  // namespace
}  // namespace rcxc

namespace rcxc {
namespace {

// A comparison's 0 or 1 applied to a variable (`x += (a < b)`) is the
// operation with the constant on the side that sets 1 (ir/joinconst.cpp):
// the values of every such operation, over a range of a whose tests go
// both ways, against what int16_t arithmetic gives here; a division by the
// truth, which the firmware leaves unchanged on 0, goes entirely.
TEST(JoinConstant, ATruthAppliedToAVariableComputesTheSame) {
  const char* text = R"(
int a, p, m, o, q, d, n;
task main() {
  p = 0; m = 0; o = 0; q = 1; d = 7; n = -32768;
  a = -3;
  repeat (8) {
    p += (a < 2);
    m -= (a != 0);
    o |= (a >= 3) * 4;
    q *= (a != 4);
    d /= (a < 1);
    n &= (a == 1);
    a += 1;
  }
}
)";
  short p = 0, m = 0, o = 0, q = 1, d = 7, n = -32768;
  for (int a = -3; a < 5; ++a) {
    p = static_cast<short>(p + (a < 2));
    m = static_cast<short>(m - (a != 0));
    o = static_cast<short>(o | (a >= 3) * 4);
    q = static_cast<short>(q * (a != 4));
    if (a < 1) d = static_cast<short>(d / 1);  // a division by 0 leaves d
    n = static_cast<short>(n & (a == 1));
  }
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto mach = test::run_image(c.out->image, 5000);
    EXPECT_EQ(test::global_value(mach, c.out->image, "p"), p);
    EXPECT_EQ(test::global_value(mach, c.out->image, "m"), m);
    EXPECT_EQ(test::global_value(mach, c.out->image, "o"), o);
    EXPECT_EQ(test::global_value(mach, c.out->image, "q"), q);
    EXPECT_EQ(test::global_value(mach, c.out->image, "d"), d);
    EXPECT_EQ(test::global_value(mach, c.out->image, "n"), n);
  }
  // x += (a < b): a test and `x += 1` (12 bytes) where -O1 sets a
  // temporary to 0, tests, sets it to 1 and adds it (22).
  const char* one = "int a, b, x;\ntask main() {\n  x += (a < b);\n}\n";
  auto o1 = test::compile_program(one, ir::OptLevel::O1), o2 = test::compile_program(one, ir::OptLevel::O2);
  ASSERT_TRUE(o1.out && o2.out);
  EXPECT_EQ(o2.out->code_bytes, o1.out->code_bytes - 10);
}

// A slot #pragma reserve keeps is a variable to the passes too (a global
// fixed in that slot): `@11 = g + @10 * 2` computes in @11 and `@11 <<= 2`
// multiplies it, where the raw instructions written by number went through
// a temporary (51 bytes). By hand at -O2: the startup's power and direction
// (4 + 2 bytes), then g = 5, @10 = 3, @11 = @10, @11 *= 2, @11 += g,
// @11 *= 4, five bytes each: 36.
TEST(Coalesce, AReservedSlotIsComputedInPlace) {
  const char* text = R"(
#pragma reserve 10 11
int g;
task main() {
  g = 5; @10 = 3;
  @11 = g + @10 * 2;
  @11 <<= 2;
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(m.state().vars[10], 3);
    EXPECT_EQ(m.state().vars[11], 44);
    EXPECT_EQ(test::global_value(m, c.out->image, "g"), 5);
    if (level == ir::OptLevel::O2) {
      EXPECT_EQ(c.out->code_bytes, 36);
    }
  }
}

// x = abs(x) and x = sign(x) are one instruction each, reading x before
// writing it, at every level (as nqc writes them): a temporary and a copy
// made them 10 bytes each where nqc's are 5, so a program of them was
// larger than nqc's (faithfulness round 16's xa14).
TEST(Coalesce, AbsAndSignOfTheTargetAreOneInstruction) {
  const char* text = R"(
int a, b;
task main() {
  a = Timer(0) - 9; b = Timer(0) - 4;
  a = abs(a);
  b = sign(b);
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "a"), 9);
    EXPECT_EQ(test::global_value(m, c.out->image, "b"), -1);
    // startup 6, two set-and-subtract pairs 20, abs and sgn 5 each.
    EXPECT_EQ(c.out->code_bytes, 36) << static_cast<int>(level);
  }
}

// abs and sign of ++x read x once it is stepped, and of an expression
// write their target once: `x = sign(++x)` is `add x, 1; sgn x, x` and
// `y = abs(x - y)` is `set t, x; sub t, y; abs y, t`, as nqc writes them
// (rcxc's were 31 and 20 bytes against nqc's 21 and 15: faithfulness
// round 18's L1 and L2, the only shapes of that round larger than nqc's).
TEST(Coalesce, AbsAndSignOfAStepOrAnExpressionWriteTheirTargetOnce) {
  const char* text = R"(
int x, y, r;
task main() {
  x = Timer(0) - 9; y = Timer(0) - 4;
  x = sign(++x);
  r = abs(--y) + 1;
  y = abs(x - y);
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 1000);
    EXPECT_EQ(test::global_value(m, c.out->image, "x"), -1);
    EXPECT_EQ(test::global_value(m, c.out->image, "r"), 6);
    EXPECT_EQ(test::global_value(m, c.out->image, "y"), 4);
    // startup 6, two set-and-subtract pairs 20, then 10, 15 and 15: nqc's 66.
    EXPECT_EQ(c.out->code_bytes, 66) << static_cast<int>(level);
  }
}

}  // namespace
}  // namespace rcxc
