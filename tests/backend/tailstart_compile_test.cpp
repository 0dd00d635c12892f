// Tail starts (ir/tailstart.cpp) and exits laid out last (ir/layout.cpp) in
// compiled programs: the bytes they save, and that the program still does
// what -O1's code, which starts every task as written, does.
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

using namespace rcxc;

namespace {

bool moved(const test::Compiled& c) { return test::logged(c.log, "runs in main"); }

std::size_t tasks_in(const test::Compiled& c) {
  std::size_t n = 0;
  for (int t = 0; t < 10; ++t) n += c.out->image.find(rcx::FragmentType::Task, t) != nullptr;
  return n;
}

}  // namespace

TEST(TailStartCompile, MainBecomesTheTaskOnEitherSideOfItsLastIf) {
  // Whichever side the random wait and the message pick, main's last act
  // is a start: both tasks run in main, and the side that ends lies last,
  // so neither start nor the jump over the endless side is left (6 bytes).
  const char* src = R"(
    task chime() { PlayTone(440, 20); Wait(30); PlayTone(660, 20); }
    task patrol() {
      while (true) { OnFwd(OUT_A); Wait(70); OnRev(OUT_A); Wait(40); Off(OUT_A); Wait(10); }
    }
    task main() {
      Wait(Random(30));
      if (Random(3) > 1) start patrol;
      else { PlaySound(1); Wait(20); start chime; }
    })";
  auto os = test::expect_same_as_o1(src, 12, 3'000);
  ASSERT_TRUE(os.out);
  EXPECT_TRUE(moved(os));
  EXPECT_EQ(tasks_in(os), 1u);
  auto o1 = test::compile_program(src, ir::OptLevel::O1);
  ASSERT_TRUE(o1.out);
  EXPECT_EQ(tasks_in(o1), 3u);
  const auto* main = os.out->image.find(rcx::FragmentType::Task, 0);
  ASSERT_NE(main, nullptr);
  // startup 6, wait 4, set + test of Random(3) 12, sound 2, wait 4, two
  // tones 8, wait 4, the patrol loop 22 (3 waits, 2 directions, on, off,
  // jump back).
  EXPECT_EQ(main->code.size(), 6u + 4u + 12u + 2u + 4u + 8u + 4u + 22u);
}

TEST(TailStartCompile, NothingMovesWhenSomethingStopsMain) {
  // `stop main` must not stop the worker's beeps: main keeps its start.
  auto os = test::expect_same_as_o1(R"(
    task worker() { repeat (10) { PlaySound(1); Wait(20); } }
    task other() { Wait(50); stop main; }
    task main() { start other; start worker; })");
  ASSERT_TRUE(os.out);
  EXPECT_FALSE(moved(os));
  EXPECT_EQ(tasks_in(os), 3u);
}

TEST(TailStartCompile, StartsAtTheEndAreNotReordered) {
  // check is started once and never stopped, but move (stopped and
  // restarted by check) is started last. Starting move first to let main
  // become check would run move's first instructions ahead of check's: all
  // three tasks stay.
  auto os = test::expect_same_as_o1(R"(
    task move() { while (true) { OnFwd(OUT_A+OUT_C); Wait(100); OnRev(OUT_C); Wait(85); } }
    task check() {
      repeat (3) { Wait(130); stop move; PlaySound(2); OnRev(OUT_A+OUT_C); Wait(40); start move; }
      stop move;
      Off(OUT_A+OUT_C);
    }
    task main() { start check; start move; })",
                                    1, 3'000);
  ASSERT_TRUE(os.out);
  EXPECT_FALSE(moved(os));
  EXPECT_EQ(tasks_in(os), 3u);
}

TEST(TailStartCompile, ATaskStartedAfterAnEarlierOneThatSharesNothingRunsInMain) {
  // beacon (numbered first) only sends messages; drive only drives and
  // reads its own sensor. Whichever takes its turn first, nothing shows
  // it: main runs drive. Had drive played a sound too, or set output A,
  // it would stay a task.
  const char* src = R"(
    task beacon() { while (true) { SendMessage(1); Wait(10); } }
    task drive() {
      SetSensor(SENSOR_2, SENSOR_TOUCH);
      while (true) { OnFwd(OUT_C); until (SENSOR_2 == 1); Off(OUT_C); Wait(20); }
    }
    task main() { OnFwd(OUT_A); start beacon; start drive; })";
  auto os = test::expect_same_as_o1(src, 1, 3'000);
  ASSERT_TRUE(os.out);
  EXPECT_TRUE(test::logged(os.log, "task drive runs in main"));
  EXPECT_EQ(tasks_in(os), 2u);
}
