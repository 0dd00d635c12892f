// Back-and-forth loops (ir/flip.cpp) in compiled programs: the bytes they
// save, and that the outputs still go one way and back as -O1's code has
// them, pass after pass.
#include <gtest/gtest.h>

#include "tests/support/compiled.h"

using namespace rcxc;

namespace {

bool flipped(const test::Compiled& c) { return test::logged(c.log, "direction flip"); }

}  // namespace

TEST(FlipCompile, TheTutorialsDriveAndMusicSavesSixBytes) {
  // 07_drive_music's main: the loop was dir, on, wait, dir, wait, jump
  // (16 bytes); now on, wait, flip, jump (10): the startup code already
  // set the first direction.
  auto os = test::expect_same_as_o1(R"(
    task music() {
      while (true) { PlayTone(262,40); Wait(50); PlayTone(294,40); Wait(50); }
    }
    task main() {
      start music;
      while (true) { OnFwd(OUT_A+OUT_B); Wait(300); OnRev(OUT_A+OUT_B); Wait(300); }
    })",
                                    1, 30'000);
  ASSERT_TRUE(os.out);
  EXPECT_TRUE(flipped(os));
  const auto* main = os.out->image.find(rcx::FragmentType::Task, 0);
  ASSERT_NE(main, nullptr);
  EXPECT_EQ(main->code.size(), 6u + 2u + 10u);  // startup, start music, the loop
}

TEST(FlipCompile, StepsBeforeTheTurnAndAReverseFirstHalf) {
  auto os = test::expect_same_as_o1(R"(
    int n;
    task main() {
      SetPower(OUT_C, 3);
      while (true) {
        PlaySound(1); n++;
        OnRev(OUT_C); Wait(40); Float(OUT_C); Wait(10);
        PlaySound(1); n++;
        OnFwd(OUT_C); Wait(40); Float(OUT_C); Wait(10);
      }
    })");
  EXPECT_TRUE(flipped(os));
}

TEST(FlipCompile, AnotherTaskTurningTheOutputKeepsTheLoopWrittenOut) {
  // Each pass of the written-out loop sets the direction again after
  // `other` turned it; a flip would keep going the wrong way.
  auto os = test::expect_same_as_o1(R"(
    task other() { Wait(450); OnRev(OUT_A); }
    task main() {
      start other;
      while (true) { OnFwd(OUT_A); Wait(100); OnRev(OUT_A); Wait(100); }
    })");
  EXPECT_FALSE(flipped(os));
}
