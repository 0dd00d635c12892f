// Edge cases of the audit against the firmware reference (seeds/000): the
// 16-bit extremes of every arithmetic opcode, Test and branch reading each
// source type, loop counters and waits from variables and the random source,
// and datalog values from each datalog source. Every expected number is
// worked out by hand from the reference (or, where it is silent, from the
// choice docs/emulator.md states) in the comment beside it.
#include <gtest/gtest.h>

#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;
using rcx::kMicrosPerMs;

// ---------------------------------------------------------------- arithmetic at 16 bits

TEST(VmEdges, DivideAndMultiplyOfMinus32768WrapAt16Bits) {
  // -32768 / -1 = 32768 and -32768 * -1 = 32768 do not fit: both wrap to -32768.
  // -32768 * 2 = -65536 wraps to 0; 32767 * 32767 = 0x3fff0001 keeps 0x0001.
  auto m = run_task(code({set(0, -32768), div(0, IMM, -1), set(1, -32768), mul(1, -1), set(2, -32768), mul(2, 2),
                          set(3, 32767), mul(3, 32767)}));
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(var(m, 0), -32768);
  EXPECT_EQ(var(m, 1), -32768);
  EXPECT_EQ(var(m, 2), 0);
  EXPECT_EQ(var(m, 3), 1);
}

TEST(VmEdges, DivisionTruncatesTowardZeroForEverySignPair) {
  // 7 / -2 = -3.5 -> -3; -7 / -2 = 3.5 -> 3; -7 / 2 -> -3; 1 / -32768 -> 0.
  auto m = run_task(code({set(0, 7), div(0, IMM, -2), set(1, -7), div(1, IMM, -2), set(2, -7), div(2, IMM, 2),
                          set(3, 1), div(3, IMM, -32768)}));
  EXPECT_EQ(var(m, 0), -3);
  EXPECT_EQ(var(m, 1), 3);
  EXPECT_EQ(var(m, 2), -3);
  EXPECT_EQ(var(m, 3), 0);
}

TEST(VmEdges, SubtractAndAddWrapBothWays) {
  // -32768 - 32767 = -65535 = 1 (mod 65536); 30000 + 30000 (from the variable
  // itself) = 60000 = -5536.
  auto m = run_task(code({set(0, -32768), sub(0, 32767), set(1, 30000), var_op(0x24, 1, VAR, 1)}));
  EXPECT_EQ(var(m, 0), 1);
  EXPECT_EQ(var(m, 1), -5536);
}

TEST(VmEdges, AndOrWorkOnAllSixteenBitsOfNegativeValues) {
  // -1 = 0xffff & 0x00ff = 255; 0xff00 (-256) | 0x000f = 0xff0f = -241;
  // 0x8000 & -1 = 0x8000 = -32768.
  auto m = run_task(code({set(0, -1), band(0, 0x00ff), set(1, -256), bor(1, 0x000f), set(2, -32768), band(2, -1)}));
  EXPECT_EQ(var(m, 0), 255);
  EXPECT_EQ(var(m, 1), -241);
  EXPECT_EQ(var(m, 2), -32768);
}

TEST(VmEdges, AbsoluteValueAndSignFromAVariable) {
  // The reference's rule for -32768 holds for a variable operand too; sign of -32768 is -1.
  auto m = run_task(code({set(8, -32768), var_op(0x74, 0, VAR, 8), var_op(0x64, 1, VAR, 8), set(9, 32767),
                          var_op(0x74, 2, VAR, 9), var_op(0x64, 3, VAR, 9)}));
  EXPECT_EQ(var(m, 0), 32767);
  EXPECT_EQ(var(m, 1), -1);
  EXPECT_EQ(var(m, 2), 32767);
  EXPECT_EQ(var(m, 3), 1);
}

// ---------------------------------------------------------------- test and branch, source by source

namespace {

struct Expected {
  int source, argument, value;
};

// A brick where every source has a known value at the checks (1 ms per instruction):
//   touch sensor on input 1 pressed (raw 100) and message 7 at 1000 ms;
//   output A on, reverse, power 5; the clock set to 1:30; var 30 = -5;
//   the checks run after a wait from 6 ms to 2506 ms, when timer 0 (never
//   cleared, counting from power-on) reads 25 tenths.
const Expected kSources[] = {
    {VAR, 30, -5},
    {TIMER, 0, 25},
    {MOTOR, 0, 0x80 | 0x08 | 5},  // on, reverse, power 5
    {SENSOR, 0, 1},               // touch: boolean mode, pressed
    {SENSTYPE, 0, 1},             // touch
    {SENSMODE, 0, 1 << 5},        // boolean, slope 0
    {SENSRAW, 0, 100},
    {SENSBOOL, 0, 1},
    {CLOCK, 0, 90},               // 1:30, and 2.5 s is not a minute
    {MESSAGE, 0, 7},
};

Bytes source_setup() {
  return code({senstype(0, 1), pwr(0x01, IMM, 5), dir(0x01), out(0x81), settime(1, 30), set(30, -5), wait(250)});
}

rcx::Machine run_checks(const Bytes& checks) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({source_setup(), checks})}}));
  m.schedule({1000 * kMicrosPerMs, rcx::SensorRawInput{0, 100}});
  m.schedule({1000 * kMicrosPerMs, rcx::MessageInput{7}});
  m.start_program();
  m.run(10'000 * kMicrosPerMs);
  return m;
}

}  // namespace

TEST(VmEdges, TestAndBranchReadsEverySourceAsItsSecondValue) {
  // For check i: "chk != immediate, source" branches over "set var i = 1"
  // (offset 6 from the offset byte = past the 5-byte set) when they differ.
  Bytes checks;
  for (std::size_t i = 0; i < std::size(kSources); ++i) {
    const auto& e = kSources[i];
    checks = code({checks, chk(2, IMM, e.value, e.source, e.argument, 6), set(static_cast<int>(i), 1)});
  }
  auto m = run_checks(checks);
  ASSERT_EQ(m.stop().kind, rcx::StopKind::Ended);
  for (std::size_t i = 0; i < std::size(kSources); ++i)
    EXPECT_EQ(var(m, static_cast<int>(i)), 1) << "source " << kSources[i].source;
}

TEST(VmEdges, TestAndBranchReadsEverySourceAsItsFirstValue) {
  // The same values with the source first, compared with var 31 holding the
  // expected value: == branches over "set var 10+i = 1" (which stays 0), !=
  // falls through to "set var 20+i = 1".
  Bytes checks;
  for (std::size_t i = 0; i < std::size(kSources); ++i) {
    const auto& e = kSources[i];
    checks = code({checks, set(31, e.value), chk(3, e.source, e.argument, VAR, 31, 6), set(10 + static_cast<int>(i), 1),
                   chk(2, e.source, e.argument, VAR, 31, 6), set(20 + static_cast<int>(i), 1)});
  }
  auto m = run_checks(checks);
  ASSERT_EQ(m.stop().kind, rcx::StopKind::Ended);
  for (std::size_t i = 0; i < std::size(kSources); ++i) {
    EXPECT_EQ(var(m, 10 + static_cast<int>(i)), 0) << "== branched for source " << kSources[i].source;
    EXPECT_EQ(var(m, 20 + static_cast<int>(i)), 1) << "!= fell through for source " << kSources[i].source;
  }
}

TEST(VmEdges, TestAndBranchComparesSignedAtTheExtremes) {
  // -32768 <= 32767 is true; 32767 >= -32768 is true; -1 <= 0 true; 0 >= -1 true.
  // Each true relation branches over the set, so vars 0..3 stay 0; var 4 is
  // the control: 32767 <= -32768 is false, so var 4 = 1.
  auto m = run_task(code({set(10, 32767), set(11, -32768), set(12, 0), set(13, -1),
                          chk(0, IMM, -32768, VAR, 10, 6), set(0, 1),
                          chk(1, IMM, 32767, VAR, 11, 6), set(1, 1),
                          chk(0, IMM, -1, VAR, 12, 6), set(2, 1),
                          chk(1, IMM, 0, VAR, 13, 6), set(3, 1),
                          chk(0, IMM, 32767, VAR, 11, 6), set(4, 1)}));
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_EQ(var(m, 2), 0);
  EXPECT_EQ(var(m, 3), 0);
  EXPECT_EQ(var(m, 4), 1);
}

// ---------------------------------------------------------------- loop counters and waits from sources

TEST(VmEdges, LoopCounterFromANegativeVariableRunsTheBodyNoTimes) {
  // loops var1 (= -3); the first decrement gives -4 < 0: pop and leave.
  // 5 loops; 8 loopc -> 17 (9 + 8); 10 add; 15 jmp -> 8 (16 - 136 + 128).
  auto m = run_task(code({set(1, -3), loops(VAR, 1), loopc(8), add(0, 1), jmp(136), setv(2, VAR, 0)}));
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(m.task(0).loop_depth, 0);
}

TEST(VmEdges, LoopCounterFromTheRandomSourceRunsZeroToMaxTimes) {
  // Random(0) is 0: no iteration. Random(5) is 0..5 iterations.
  // 0 loops; 3 loopc -> 12; 5 add var0; 10 jmp -> 3; 12 loops; 15 loopc -> 24; 17 add var1; 22 jmp -> 15.
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    rcx::Config c = ms_config();
    c.seed = seed;
    auto m = run(image({{0, code({loops(RANDOM, 0), loopc(8), add(0, 1), jmp(136), loops(RANDOM, 5), loopc(8),
                                  add(1, 1), jmp(136)})}}),
                 10'000, c);
    ASSERT_EQ(m.stop().kind, rcx::StopKind::Ended);
    EXPECT_EQ(var(m, 0), 0);
    EXPECT_GE(var(m, 1), 0);
    EXPECT_LE(var(m, 1), 5);
  }
}

TEST(VmEdges, NegativeWaitDoesNotWait) {
  // Wait var0 (= -1) at 1 ms: no delay (docs: a negative delay waits 0), so the
  // output goes on at 2 ms, after the wait's own 1 ms.
  auto m = run_task(code({set(0, -1), waitv(VAR, 0), out(0x81)}));
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].t_us, 2 * kMicrosPerMs);
}

TEST(VmEdges, RandomWaitIsZeroToMaxHundredths) {
  // Wait random(50) at 0 ms wakes the task n hundredths after the wait began,
  // n in 0..50; the output goes on then, or at 1 ms (the wait's own cost)
  // when n is 0.
  bool some_wait = false;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    rcx::Config c = ms_config();
    c.seed = seed;
    auto m = run(image({{0, code({waitv(RANDOM, 50), out(0x81)})}}), 10'000, c);
    auto outs = events_of(m, rcx::EventKind::Output);
    ASSERT_EQ(outs.size(), 1u);
    rcx::Micros t = outs[0].t_us;
    EXPECT_TRUE(t == kMicrosPerMs || (t % (10 * kMicrosPerMs) == 0 && t <= 500 * kMicrosPerMs)) << t;
    some_wait = some_wait || t > kMicrosPerMs;
  }
  EXPECT_TRUE(some_wait);
}

TEST(VmEdges, MotorPowerFromTheRandomSourceStaysInZeroToSeven) {
  // Random(7) always gives a valid power; Random(20) gives 8..20 part of the
  // time, which the reference says is ignored, so the power is never above 7.
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    rcx::Config c = ms_config();
    c.seed = seed;
    auto m = run(image({{0, code({pwr(0x01, RANDOM, 7), pwr(0x02, IMM, 2), pwr(0x02, RANDOM, 20)})}}), 10'000, c);
    EXPECT_LE(m.state().outputs[0].power, 7);
    EXPECT_LE(m.state().outputs[1].power, 7);
  }
}

// ---------------------------------------------------------------- datalog values by source

TEST(VmEdges, DatalogEntriesHoldTheSourceValues) {
  // Entries written after the wait (6 ms .. 2506 ms): var 30 = -5 (type 30),
  // timer 0 = 25 tenths (0x20), sensor 1 = 1 (0x40), clock = 90 (0x80).
  rcx::Machine m = run_checks(code({logsize(4), lognext(VAR, 30), lognext(TIMER, 0), lognext(SENSOR, 0),
                                     lognext(CLOCK, 0)}));
  const auto& log = m.state().datalog;
  ASSERT_EQ(log.size(), 4u);
  EXPECT_EQ(log[0].type, 30);
  EXPECT_EQ(log[0].value, -5);
  EXPECT_EQ(log[1].type, 0x20);
  EXPECT_EQ(log[1].value, 25);
  EXPECT_EQ(log[2].type, 0x40);
  EXPECT_EQ(log[2].value, 1);
  EXPECT_EQ(log[3].type, 0x80);
  EXPECT_EQ(log[3].value, 90);
  // Upload: entry 0 is the current size, counting itself: 1 + 4.
  auto up = m.upload_datalog(0, 1);
  ASSERT_EQ(up.size(), 1u);
  EXPECT_EQ(up[0].type, 0xff);
  EXPECT_EQ(up[0].value, 5);
}

// ---------------------------------------------------------------- out-of-range operands (docs: our choices)

TEST(VmEdges, LoopCounterFromAVariableKeepsItsSixteenBits) {
  // loops var1 (= 300): the body runs 300 times, not 300 & 0xff = 44.
  auto m = run_task(code({set(1, 300), loops(VAR, 1), loopc(8), add(0, 1), jmp(136)}));
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(var(m, 0), 300);
}

TEST(VmEdges, IndicesOutsideTheReferenceRangesReadZeroAndWriteNothing) {
  // var 40 is written to nothing and reads 0; timer 4, motor 3, sensor 3 read 0;
  // Clear timer 4 and Clear sensor value 3 are ignored and the run goes on.
  auto m = run_task(code({set(40, 123), set(0, 9), setv(0, VAR, 40), set(1, 9), setv(1, TIMER, 4), set(2, 9),
                          setv(2, MOTOR, 3), set(3, 9), setv(3, SENSOR, 3), timerclr(4), sensclr(3), set(4, 1)}));
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_EQ(var(m, 2), 0);
  EXPECT_EQ(var(m, 3), 0);
  EXPECT_EQ(var(m, 4), 1);
}

TEST(VmEdges, TaskSubroutineSlotAndSensorTypeOutsideTheirRangesAreIgnoredByAProgram) {
  // Call 8, Start/Stop/Delete task 10, Delete subroutine 8, Set program
  // number 5, a sensor type 5 and a sensor 3 do nothing; the run goes on.
  auto m = run(image({{0, code({call(8), start(10), stop(10), deltask(10), delsub(8), program(5), senstype(0, 5),
                                senstype(3, 1), sensmode(3, 0x20), setv(1, SENSTYPE, 0), set(0, 1)})}},
                     {{0, code({set(2, 1)})}}));
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(m.program(), 0);
  EXPECT_EQ(var(m, 0), 1);
  EXPECT_EQ(var(m, 1), 0);  // sensor 1 is still raw
  EXPECT_EQ(var(m, 2), 0);  // sub 0 was not called in place of 8
  EXPECT_TRUE(m.slot(0).subs[0].has_value());
}

TEST(VmEdges, SetMessageInAProgramIsNoArrival) {
  // Set message (0xf7) run by the program fills the buffer, as the reference
  // says, but nothing came in by infrared: no message_received event. One that
  // does arrive (a scenario input at 0 ms) is logged.
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({wait(10), msgset(9), setv(0, MESSAGE, 0)})}}));
  m.schedule({0, rcx::MessageInput{4}});
  m.start_program();
  m.run(1'000 * kMicrosPerMs);
  EXPECT_EQ(var(m, 0), 9);
  auto received = events_of(m, rcx::EventKind::MessageReceived);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].value, 4);
}
