// Outlining (backend/outline.h) on whole programs: what moves into a new
// subroutine, what must stay, and that the result still runs the same on
// the emulator.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/support/compiled.h"

using namespace rcxc;

namespace {

test::Compiled compile(const std::string& text, ir::OptLevel level = ir::OptLevel::Os) {
  return test::compile_program(text, level);
}

std::size_t subroutines(const backend::Output& out) {
  return static_cast<std::size_t>(std::count_if(out.image.fragments.begin(), out.image.fragments.end(), [](const auto& f) {
    return f.type == rcx::FragmentType::Subroutine;
  }));
}

std::size_t count_byte(const std::vector<std::uint8_t>& code, std::uint8_t b) {
  return static_cast<std::size_t>(std::count(code.begin(), code.end(), b));
}

int run_for_global(const rcx::Image& image, const std::string& name, std::int64_t ms) {
  return test::global_value(test::run_image(image, ms), image, name);
}

}  // namespace

TEST(Outline, ThreeEqualWaitsShareASubroutine) {
  // 3 x `wait 200` (4 bytes each) = 12 bytes; 3 calls + the wait + the
  // firmware's return = 11.
  auto c = compile("task main() { PlaySound(1); Wait(200); PlaySound(2); Wait(200); PlaySound(3); Wait(200); }");
  ASSERT_TRUE(c.out);
  EXPECT_EQ(subroutines(*c.out), 1u);
  EXPECT_EQ(count_byte(c.out->image.find(rcx::FragmentType::Task, 0)->code, 0x17), 3u);
  auto noout = compile("task main() { PlaySound(1); Wait(200); PlaySound(2); Wait(200); PlaySound(3); Wait(200); }",
                       ir::OptLevel::O1);
  ASSERT_TRUE(noout.out);
  EXPECT_EQ(subroutines(*noout.out), 0u);
  EXPECT_LT(c.out->code_bytes, noout.out->code_bytes);
}

TEST(Outline, TwoEqualWaitsDoNotPay) {
  // 2 x 4 bytes against 2 calls + 4 + return: nothing saved.
  auto c = compile("task main() { PlaySound(1); Wait(200); PlaySound(2); Wait(200); }");
  ASSERT_TRUE(c.out);
  EXPECT_EQ(subroutines(*c.out), 0u);
}

TEST(Outline, ABusyWaitMovesWithTheCodeAfterIt) {
  // `until (sem == 0); sem = 1;` three times: the test branches to itself,
  // so the whole pair moves into one subroutine and still waits there.
  const char* src = R"(
    int sem, done;
    task other() {
      until (sem == 0); sem = 1; Wait(5); sem = 0;
      until (sem == 0); sem = 1; done += 10; sem = 0;
    }
    task main() {
      sem = 1; start other; Wait(50);
      sem = 0; Wait(1);
      until (sem == 0); sem = 1; done += 1; sem = 0;
    })";
  auto c = compile(src);
  ASSERT_TRUE(c.out);
  const rcx::Fragment* sub = nullptr;
  for (const auto& f : c.out->image.fragments)
    if (f.type == rcx::FragmentType::Subroutine && !f.code.empty() && f.code[0] == 0x85) sub = &f;
  ASSERT_NE(sub, nullptr) << "no subroutine starting with the busy wait";
  // chk 0 != sem, back onto itself (offset -6 from its offset field), then sem = 1.
  EXPECT_EQ(sub->code.at(6), 0xfa);
  EXPECT_EQ(sub->code.at(7), 0x14);
  EXPECT_EQ(run_for_global(c.out->image, "done", 2000), 11);
  auto plain = compile(src, ir::OptLevel::O1);
  ASSERT_TRUE(plain.out);
  EXPECT_EQ(run_for_global(plain.out->image, "done", 2000), 11);
  EXPECT_LT(c.out->code_bytes, plain.out->code_bytes);
}

TEST(Outline, CodeEnteredInTheMiddleIsNotCutThere) {
  // Each `x += 1; do { y += 1; ... }` is entered at `y += 1` by the loop's
  // back branch: a subroutine may start there, but one starting at
  // `x += 1` and running into the loop would count x once per iteration.
  const char* src = R"(
    int x, y, n;
    task main() {
      x = 0; y = 0; n = 0;
      x += 1; do { y += 1; n += 1; } while (n < 3);
      x += 1; do { y += 1; n += 1; } while (n < 6);
      x += 1; do { y += 1; n += 1; } while (n < 9);
    })";
  auto c = compile(src);
  ASSERT_TRUE(c.out);
  EXPECT_GT(subroutines(*c.out), 0u);
  EXPECT_EQ(run_for_global(c.out->image, "x", 1000), 3);
  EXPECT_EQ(run_for_global(c.out->image, "y", 1000), 9);
}

TEST(Outline, ALoopTestBranchingBeforeTheSequenceStaysInTheTask) {
  // The three loops end alike (`y += 1; z += 1;` and the test) but start
  // differently: their tests branch back before the common part, so the
  // test cannot move into a subroutine with it.
  const char* src = R"(
    int x, y, z, lim;
    task main() {
      x = 0; y = 0; z = 0;
      lim = 3; do { x += 1; y += 1; z += 1; } while (z != lim);
      lim = 6; do { x += 2; y += 1; z += 1; } while (z != lim);
      lim = 9; do { x += 3; y += 1; z += 1; } while (z != lim);
    })";
  auto c = compile(src);
  ASSERT_TRUE(c.out);
  EXPECT_GT(subroutines(*c.out), 0u);
  EXPECT_EQ(run_for_global(c.out->image, "x", 1000), 18);
  EXPECT_EQ(run_for_global(c.out->image, "y", 1000), 9);
}

TEST(Outline, AWholeRepeatLoopMovesWithItsCounter) {
  // The same counted loop in two tasks and twice in main, once nested in
  // another repeat: each copy (loopset, loopdec, body, jump back: 18 bytes)
  // becomes a call. The loop's exit goes just past the copy, which in the
  // subroutine is its end: the return. The counters are the calling task's,
  // at the depth of the call, as they were in place.
  const char* src = R"(
    int n, m;
    task other() { repeat (3) { PlaySound(1); n++; Wait(10); } }
    task main() {
      start other;
      repeat (3) { PlaySound(1); n++; Wait(10); }
      repeat (2) { m++; repeat (3) { PlaySound(1); n++; Wait(10); } }
      Wait(50);
    })";
  auto c = compile(src);
  ASSERT_TRUE(c.out);
  ASSERT_EQ(subroutines(*c.out), 1u);
  const auto* sub = c.out->image.find(rcx::FragmentType::Subroutine, 0);
  ASSERT_NE(sub, nullptr);
  EXPECT_EQ(sub->code.front(), rcx::info(rcx::Op::SetLoopCounter).code);
  EXPECT_EQ(sub->code.size(), 18u);
  EXPECT_EQ(count_byte(c.out->image.find(rcx::FragmentType::Task, 1)->code, 0x17), 1u);
  EXPECT_EQ(run_for_global(c.out->image, "n", 2000), 12);
  EXPECT_EQ(run_for_global(c.out->image, "m", 2000), 2);
}

TEST(Outline, ARepeatedPassageLongerThanTheSearchWindowMovesWhole) {
  // A passage of 30 tones and 3 counts (135 bytes) played twice: the
  // search looks 24 instructions from each start, then the chosen sequence
  // grows over all the passage its two places share. One subroutine with
  // the whole passage and two calls, not a 24-instruction piece and a
  // second subroutine for the rest (one call, one return more per play).
  std::string passage;
  for (int k = 0; k < 30; ++k) {
    passage += "PlayTone(" + std::to_string(200 + (k * k * 7) % 500) + ", 5);\n";
    if (k % 10 == 9) passage += "n += 1;\n";
  }
  std::string src = "int n, x;\ntask main() {\nx = 1;\n" + passage + "x = 2;\nWait(20);\n" + passage + "x = 3;\n}\n";
  auto c = compile(src);
  ASSERT_TRUE(c.out);
  ASSERT_EQ(subroutines(*c.out), 1u);
  EXPECT_EQ(c.out->image.find(rcx::FragmentType::Subroutine, 0)->code.size(), 135u);
  EXPECT_EQ(count_byte(c.out->image.find(rcx::FragmentType::Task, 0)->code, 0x17), 2u);
  EXPECT_EQ(run_for_global(c.out->image, "n", 5000), 6);
  EXPECT_EQ(run_for_global(c.out->image, "x", 5000), 3);
}

TEST(Outline, APassagePlayedTwiceInARowGrowsUpToItsSecondCopy) {
  // The same 30 tones twice back to back: each place grows until it meets
  // the other, never over it, so the task is two calls of one 120-byte
  // subroutine.
  std::string passage;
  for (int k = 0; k < 30; ++k) passage += "PlayTone(" + std::to_string(300 + (k * k * 11) % 700) + ", 3);\n";
  std::string src = "int x;\ntask main() {\nx = 1;\n" + passage + passage + "x = 2;\n}\n";
  auto c = compile(src);
  ASSERT_TRUE(c.out);
  ASSERT_EQ(subroutines(*c.out), 1u);
  EXPECT_EQ(c.out->image.find(rcx::FragmentType::Subroutine, 0)->code.size(), 120u);
  EXPECT_EQ(count_byte(c.out->image.find(rcx::FragmentType::Task, 0)->code, 0x17), 2u);
  EXPECT_EQ(run_for_global(c.out->image, "x", 5000), 2);
}
