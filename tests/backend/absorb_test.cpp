// Absorption (backend/absorb.h): an instruction every call of a subroutine
// has beside it moves into the subroutine. What moves, what must stay, and
// that the program still does what -O1's code (which moves nothing) does.
#include <gtest/gtest.h>

#include <algorithm>

#include "verify/compare.h"
#include "tests/support/compiled.h"

using namespace rcxc;
using test::compile_program;
using test::global_value;
using test::run_image;

namespace {

constexpr std::int64_t kRunMs = 10'000;  // sounds play from a queue, after the program's own time

const std::vector<std::uint8_t> kWait100 = {0x43, 0x02, 0x64, 0x00};
const std::vector<std::uint8_t> kWait200 = {0x43, 0x02, 0xc8, 0x00};

bool moved_any(const ir::Log& log) { return test::logged(log, "moved into it"); }

// Occurrences of an instruction's bytes in a fragment's code.
int count(const rcx::Fragment& f, const std::vector<std::uint8_t>& instr) {
  int n = 0;
  for (auto it = f.code.begin(); (it = std::search(it, f.code.end(), instr.begin(), instr.end())) != f.code.end(); ++it)
    ++n;
  return n;
}

int sounds(const rcx::Machine& m, int sound) {
  auto lines = rcx::observable_lines(m);
  return static_cast<int>(std::count_if(lines.begin(), lines.end(), [&](const std::string& l) {
    return l.ends_with("sound " + std::to_string(sound));
  }));
}

// main for a subroutine `s` and a global `x`: x = 0, then s(); PlaySound(4);
// three times.
constexpr const char* kThreeCallsEachBeforeSound4 = R"(
    task main() {
      x = 0;
      s(); PlaySound(4);
      s(); PlaySound(4);
      s(); PlaySound(4);
      Wait(50);
    })";

struct Checked {
  test::Compiled os;
  rcx::Machine run;
};

// Compiles at -Os, expects an instruction moved or not, and expects the
// run to show what -O1's code shows (as `rcxc compare` judges it).
Checked check(const std::string& src, bool moves) {
  Checked c{compile_program(src), rcx::Machine{}};
  auto o1 = compile_program(src, ir::OptLevel::O1);
  EXPECT_TRUE(c.os.out && o1.out);
  if (!c.os.out || !o1.out) return c;
  EXPECT_EQ(moved_any(c.os.log), moves);
  c.run = run_image(c.os.out->image, kRunMs);
  auto theirs = run_image(o1.out->image, kRunMs);
  auto cmp = rcx::compare_runs({&c.run, &c.os.out->image, "-Os"}, {&theirs, &o1.out->image, "-O1"});
  EXPECT_TRUE(cmp.same) << cmp.side_by_side;
  return c;
}

}  // namespace

TEST(Absorb, TheShortestWaitBeforeEveryCallMovesIntoTheSubroutine) {
  // Waits of 100, 200, 100 before the three calls: 100 moves in, the 200
  // keeps 100. 3 x 4 bytes of waits become 4 + 4.
  auto c = check(R"(
    sub turn() { OnRev(OUT_C); Wait(340); OnFwd(OUT_A+OUT_C); }
    task main() {
      OnFwd(OUT_A+OUT_C);
      Wait(100); turn();
      Wait(200); turn();
      Wait(100); turn();
      Off(OUT_A+OUT_C);
    })",
                 true);
  ASSERT_TRUE(c.os.out);
  const auto* sub = c.os.out->image.find(rcx::FragmentType::Subroutine, 0);
  const auto* task = c.os.out->image.find(rcx::FragmentType::Task, 0);
  ASSERT_TRUE(sub && task);
  EXPECT_TRUE(std::equal(kWait100.begin(), kWait100.end(), sub->code.begin()));
  EXPECT_EQ(count(*task, kWait100), 1);
  EXPECT_EQ(count(*task, kWait200), 0);
  // Counted by hand: main is the startup (6), on, call, wait, call, call,
  // off (14); the subroutine wait, dir, wait, dir (12). In place the
  // waits took 4 bytes more.
  EXPECT_EQ(c.os.out->code_bytes, 32);
}

TEST(Absorb, AnInstructionAfterEveryCallMovesIn) {
  auto c = check(R"(
    int x;
    sub chirp() { PlaySound(1); Wait(10); PlaySound(2); }
    task main() {
      chirp(); x += 1;
      chirp(); x += 1;
      chirp(); x += 1;
      Wait(20);
    })",
                 true);
  ASSERT_TRUE(c.os.out);
  const auto* sub = c.os.out->image.find(rcx::FragmentType::Subroutine, 0);
  ASSERT_TRUE(sub);
  EXPECT_EQ(sub->code.at(sub->code.size() - 5), rcx::info(rcx::Op::AddToVariable).code);
  EXPECT_EQ(global_value(c.run, c.os.out->image, "x"), 3);
}

TEST(Absorb, TheEndOfTheSubroutineStillRunsTheMovedInstruction) {
  // `if (x > 0) ...` at the end of the subroutine branches to its end when
  // x is 0: that branch must now reach the moved `PlaySound(4)`.
  auto c = check(std::string("int x;\nsub s() { PlaySound(1); Wait(10); if (x > 0) { PlaySound(2); Wait(10); } }\n") +
                     kThreeCallsEachBeforeSound4,
                 true);
  EXPECT_EQ(sounds(c.run, 4), 3);
  EXPECT_EQ(sounds(c.run, 2), 0);
}

TEST(Absorb, ALoopBackToTheSubroutinesStartSkipsTheMovedInstruction) {
  // The do-while loops back to the subroutine's first instruction, which
  // after the move is the second: PlaySound(5) must play once per call.
  auto c = check(R"(
    int n;
    sub count3() { do { n += 1; } while (n % 3 != 0); }
    task main() {
      n = 0;
      PlaySound(5); count3();
      PlaySound(5); count3();
      PlaySound(5); count3();
      Wait(50);
    })",
                 true);
  ASSERT_TRUE(c.os.out);
  EXPECT_EQ(sounds(c.run, 5), 3);
  EXPECT_EQ(global_value(c.run, c.os.out->image, "n"), 9);
}

TEST(Absorb, NothingMovesAfterCallsOfASubroutineThatReturnsEarly) {
  auto c = check(std::string("int x;\nsub s() { PlaySound(1); Wait(10); if (x == 0) return; PlaySound(2); Wait(10); }\n") +
                     kThreeCallsEachBeforeSound4,
                 false);
  EXPECT_EQ(sounds(c.run, 4), 3);
}

TEST(Absorb, ACallABranchReachesKeepsTheInstructionBeforeIt) {
  // The first call is also reached by the `if`'s false side, without the
  // PlaySound(3) before it: moving that into the subroutine would play it.
  auto c = check(R"(
    int x;
    sub s() { PlaySound(1); Wait(10); PlaySound(2); Wait(10); }
    task main() {
      x = 0;
      if (x > 0) PlaySound(3);
      s(); PlaySound(3);
      s(); PlaySound(3);
      s();
      Wait(50);
    })",
                 false);
  EXPECT_EQ(sounds(c.run, 3), 2);
  EXPECT_EQ(sounds(c.run, 1), 3);
}

TEST(Absorb, OneWholeCopyIsNotWorthMoving) {
  // Wait(100), Wait(200), Wait(300): moving 100 in would leave a wait at
  // two calls and add one to the subroutine.
  check(R"(
    sub s() { PlaySound(1); Wait(10); PlaySound(2); Wait(10); }
    task main() { Wait(100); s(); Wait(200); s(); Wait(300); s(); }
  )",
        false);
}

TEST(Absorb, ProgramsWithRawAsmAreLeftAlone) {
  // Raw bytes could hold a call the pass cannot see (here 0x17 0x00, a call
  // of sub 0 without the wait before it).
  auto c = compile_program(R"(
    sub s() { PlaySound(1); Wait(10); PlaySound(2); Wait(10); }
    task main() { Wait(100); s(); Wait(100); s(); Wait(100); s(); asm { 0x17, 0x00 }; }
  )");
  ASSERT_TRUE(c.out);
  EXPECT_FALSE(moved_any(c.log));
}

TEST(Absorb, ACallFromTwoTasksMovesTheirCommonWait) {
  // The subroutine runs in both tasks; each wait is its own task's.
  auto c = check(R"(
    int n;
    sub s() { n += 1; PlaySound(1); Wait(5); }
    task other() { Wait(30); s(); Wait(30); s(); }
    task main() { start other; Wait(30); s(); Wait(80); }
  )",
                 true);
  ASSERT_TRUE(c.os.out);
  EXPECT_EQ(global_value(c.run, c.os.out->image, "n"), 3);
}
