// One test (or more) per command opcode, with the numbers the firmware
// reference gives (branch formulas, -32768 abs, loop counter stack, ...).
#include <gtest/gtest.h>

#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;
using rcx::StopKind;

// ---------------------------------------------------------------- arithmetic

TEST(VmArithmetic, SetVariableStoresImmediate) {
  auto m = run_task(set(0, 0x1234));
  EXPECT_EQ(var(m, 0), 0x1234);
}

TEST(VmArithmetic, AddAndSubtractWrapAt16Bits) {
  auto m = run_task(code({set(0, 32767), add(0, 1), set(1, -32768), sub(1, 1)}));
  EXPECT_EQ(var(m, 0), -32768);
  EXPECT_EQ(var(m, 1), 32767);
}

TEST(VmArithmetic, MultiplyWraps) {
  auto m = run_task(code({set(0, 300), mul(0, 300)}));
  EXPECT_EQ(var(m, 0), 90000 - 65536);
}

TEST(VmArithmetic, DivideByZeroLeavesDestinationUnchanged) {
  auto m = run_task(code({set(0, 77), div(0, IMM, 0), set(1, 0), set(2, 50), div(2, VAR, 1)}));
  EXPECT_EQ(var(m, 0), 77);
  EXPECT_EQ(var(m, 2), 50);
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
}

TEST(VmArithmetic, DivideTruncatesTowardZero) {
  auto m = run_task(code({set(0, -7), div(0, IMM, 2), set(1, 100), set(2, 7), div(1, VAR, 2)}));
  EXPECT_EQ(var(m, 0), -3);
  EXPECT_EQ(var(m, 1), 14);
}

TEST(VmArithmetic, AndOr) {
  auto m = run_task(code({set(0, 0x0ff0), band(0, 0x3c3c), set(1, 0x0f00), bor(1, 0x00f0)}));
  EXPECT_EQ(var(m, 0), 0x0c30);
  EXPECT_EQ(var(m, 1), 0x0ff0);
}

TEST(VmArithmetic, AbsoluteValueOfMinus32768Is32767) {
  auto m = run_task(code({abs_(0, -32768), abs_(1, -5), abs_(2, 6)}));
  EXPECT_EQ(var(m, 0), 32767);
  EXPECT_EQ(var(m, 1), 5);
  EXPECT_EQ(var(m, 2), 6);
}

TEST(VmArithmetic, SignVariable) {
  auto m = run_task(code({sgn(0, -9), set(1, 5), sgn(1, 0), sgn(2, 1234)}));
  EXPECT_EQ(var(m, 0), -1);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_EQ(var(m, 2), 1);
}

TEST(VmArithmetic, VariableSourceReadsOtherVariable) {
  auto m = run_task(code({set(3, 40), var_op(0x24, 0, VAR, 3), var_op(0x24, 0, VAR, 3)}));
  EXPECT_EQ(var(m, 0), 80);
}

// ---------------------------------------------------------------- branch formulas

namespace {
// Places `bytes` at `address` in a zero-filled body of `size` bytes.
Bytes at(int address, const Bytes& bytes, int size = 500) {
  Bytes c(static_cast<std::size_t>(size), 0);
  std::copy(bytes.begin(), bytes.end(), c.begin() + address);
  return c;
}
int target_of(const Bytes& c, int address) { return rcx::decode_command(c, address).target; }
}  // namespace

// The addresses below come from `nqc -Trcx -L` listings of real programs.
TEST(VmBranch, NearForwardIsOffsetAddressPlusOffset) {
  EXPECT_EQ(target_of(at(35, {0x27, 0x14}), 35), 56);  // 36 + 0x14
}

TEST(VmBranch, NearBackwardUsesTheDirectionBit) {
  EXPECT_EQ(target_of(at(56, {0x27, 0xa3}), 56), 22);  // 57 - 0xa3 + 128
}

TEST(VmBranch, FarForwardAddsExtensionTimes128) {
  EXPECT_EQ(target_of(at(6, {0x72, 0x4a, 0x01}), 6), 209);  // 7 + 0x4a + 128
}

TEST(VmBranch, FarBackward) {
  EXPECT_EQ(target_of(at(434, {0x72, 0xd5, 0x01}), 434), 222);  // 435 - 0xd5 - 128 + 128
}

TEST(VmBranch, TestAndBranchOffsetsAreSignedFromTheOffsetField) {
  EXPECT_EQ(target_of(at(22, {0x85, 0x49, 0x09, 0x00, 0x00, 0x02, 0x09}), 22), 37);               // 28 + 9
  EXPECT_EQ(target_of(at(209, {0x95, 0x42, 0x00, 0xe7, 0x03, 0x00, 0x32, 0xff}), 209), 9);        // 215 - 206
}

TEST(VmBranch, DecrementLoopCounterOffsetIsUnsigned) {
  EXPECT_EQ(target_of(at(9, {0x37, 0x13}), 9), 29);                  // 10 + 0x13
  EXPECT_EQ(target_of(at(9, {0x37, 0xf0}), 9), 10 + 0xf0);           // never backwards
  EXPECT_EQ(target_of(at(9, {0x92, 0x10, 0x01}), 9), 10 + 0x110);
}

TEST(VmBranch, NearJumpSkipsBytes) {
  // jmp at 0 with its offset field at 1: 1 + 3 = 4; bytes 2..3 are not code.
  auto m = run_task(code({jmp(3), {0xff, 0xff}, set(0, 1)}));
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 0), 1);
}

TEST(VmBranch, NearBackwardLoopRuns) {
  // 0 add; 5 chk 3 <= var0 -> 14 (end); 12 jmp back to 0 (13 - 141 + 128).
  auto m = run_task(code({add(0, 1), chk(0, IMM, 3, VAR, 0, 3), jmp(141)}));
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 0), 3);
}

TEST(VmBranch, FarJumpsBothWays) {
  // 0: jmpl to 200 (1 + 71 + 128); 3: set var1; 8: stop all; 200: jmpl to 3 (201 - 198 - 128 + 128).
  Bytes c = code({jmpl(71, 1), set(1, 9), stopall()});
  c.resize(200, 0xff);
  c = code({c, jmpl(198, 1)});
  auto m = run_task(c);
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 1), 9);
}

TEST(VmBranch, BranchOutsideTheCodeFaultsWithTaskAddressOpcode) {
  auto m = run_task(code({set(0, 1), jmp(0x7f)}));  // 6 + 127 = 133 > 7
  ASSERT_EQ(m.stop().kind, StopKind::Fault);
  ASSERT_TRUE(m.stop().fault);
  EXPECT_EQ(m.stop().fault->task, 0);
  EXPECT_EQ(m.stop().fault->sub, -1);
  EXPECT_EQ(m.stop().fault->address, 5);
  EXPECT_EQ(m.stop().fault->opcode, 0x27);
  EXPECT_FALSE(m.any_task_active());
}

TEST(VmBranch, BranchToTheEndOfTheCodeEndsTheTask) {
  auto m = run_task(code({jmp(2), {0xff, 0xff}}));  // 1 + 2 = 3: lands on 0xff, not an opcode
  EXPECT_EQ(m.stop().kind, StopKind::Fault);
  auto m2 = run_task(code({jmp(3), {0xff, 0xff}}));  // 1 + 3 = 4 = code size
  EXPECT_EQ(m2.stop().kind, StopKind::Ended);
}

TEST(VmBranch, RequestOnlyOrUnknownOpcodeFaults) {
  auto m = run_task({0x10});  // Alive is a request, not a command
  ASSERT_EQ(m.stop().kind, StopKind::Fault);
  EXPECT_EQ(m.stop().fault->opcode, 0x10);
  EXPECT_EQ(m.stop().fault->address, 0);
}

TEST(VmBranch, TruncatedInstructionFaults) {
  auto m = run_task({0x14, 0x00, 0x02});
  ASSERT_EQ(m.stop().kind, StopKind::Fault);
  EXPECT_EQ(m.stop().fault->opcode, 0x14);
}

TEST(VmBranch, DisallowedSourceFaults) {
  auto m = run_task(var_op(0x24, 0, RANDOM, 5));  // add allows only sources 0 and 2
  ASSERT_EQ(m.stop().kind, StopKind::Fault);
  EXPECT_EQ(m.stop().fault->opcode, 0x24);
}

// ---------------------------------------------------------------- test and branch

namespace {
// var2 = 1 when the comparison `a op b` is false (the branch skips the set).
int taken(int op, int a, int b) {
  // 10: chk, offset field at 16, skip set(2,1) at 17..21 -> 22.
  auto m = run_task(code({set(0, a), set(1, b), chk(op, VAR, 0, VAR, 1, 6), set(2, 1)}));
  return var(m, 2) == 0 ? 1 : 0;
}
}  // namespace

TEST(VmTestAndBranch, FourComparisons) {
  EXPECT_EQ(taken(0, 3, 5), 1);  // <=
  EXPECT_EQ(taken(0, 5, 5), 1);
  EXPECT_EQ(taken(0, 6, 5), 0);
  EXPECT_EQ(taken(1, 3, 5), 0);  // >=
  EXPECT_EQ(taken(1, 5, 5), 1);
  EXPECT_EQ(taken(2, 3, 5), 1);  // !=
  EXPECT_EQ(taken(2, 5, 5), 0);
  EXPECT_EQ(taken(3, 5, 5), 1);  // ==
  EXPECT_EQ(taken(3, -1, 5), 0);
  EXPECT_EQ(taken(0, -1, 0), 1);  // signed
}

TEST(VmTestAndBranch, NegativeOffsetBranchesBack) {
  // 5: add; 10: chk var0 <= var1 back to 5 (16 - 11).
  auto m = run_task(code({set(1, 2), add(0, 1), chk(0, VAR, 0, VAR, 1, -11)}));
  EXPECT_EQ(var(m, 0), 3);
}

TEST(VmTestAndBranch, FarFormWithNegativeOffset) {
  auto m = run_task(code({set(1, 2), add(0, 1), chkl(0, VAR, 0, VAR, 1, -11)}));
  EXPECT_EQ(var(m, 0), 3);
}

// ---------------------------------------------------------------- loop counters

TEST(VmLoop, SetAndDecrementRunTheBodyNTimes) {
  // 0 loops 4; 3 loopc -> 12 (4 + 8); 5 add; 10 jmp -> 3 (11 - 136 + 128).
  auto m = run_task(code({loops(IMM, 4), loopc(8), add(0, 1), jmp(136)}));
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 0), 4);
}

TEST(VmLoop, FarDecrementAndVariableCount) {
  // 0 set var1 = 3; 5 loops var1; 8 loopcl -> 18 (9 + 9); 11 add; 16 jmp -> 8 (17 - 137 + 128).
  auto m = run_task(code({set(1, 3), loops(VAR, 1), loopcl(9), add(0, 1), jmp(137)}));
  EXPECT_EQ(var(m, 0), 3);
}

TEST(VmLoop, FifthPushOverwritesTheTop) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({loops(IMM, 1), loops(IMM, 2), loops(IMM, 3), loops(IMM, 4), loops(IMM, 5), wait(100)})}}));
  m.start_program();
  m.run_until(50 * rcx::kMicrosPerMs);
  const auto& t = m.task(0);
  EXPECT_EQ(t.loop_depth, 4);
  EXPECT_EQ(t.loops[0], 1);
  EXPECT_EQ(t.loops[1], 2);
  EXPECT_EQ(t.loops[2], 3);
  EXPECT_EQ(t.loops[3], 5);
}

TEST(VmLoop, NestedLoopsUseTheStack) {
  // outer 2 x inner 3: var0 counts inner bodies = 6.
  // 0 loops 2; 3 loopc -> 24 (4 + 20); 5 loops 3; 8 loopc -> 17 (9 + 8); 10 add; 15 jmp -> 8;
  // 17 add var1; 22 jmp -> 3
  Bytes c = code({loops(IMM, 2), loopc(20), loops(IMM, 3), loopc(8), add(0, 1), jmp(16 - 8 + 128),
                  add(1, 1), jmp(23 - 3 + 128)});
  ASSERT_EQ(c.size(), 24u);
  auto m = run_task(c);
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 0), 6);
  EXPECT_EQ(var(m, 1), 2);
}

// ---------------------------------------------------------------- subroutines

TEST(VmSub, CallRunsTheSubThenReturns) {
  auto m = run(image({{0, code({call(0), add(0, 1)})}}, {{0, set(0, 7)}}));
  EXPECT_EQ(var(m, 0), 8);
}

TEST(VmSub, ReturnInTheMiddle) {
  auto m = run(image({{0, code({call(0), add(0, 1)})}}, {{0, code({set(0, 7), ret(), set(0, 99)})}}));
  EXPECT_EQ(var(m, 0), 8);
}

TEST(VmSub, CallOfUndefinedSubDoesNothing) {
  auto m = run_task(code({call(3), set(0, 1)}));
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 0), 1);
}

TEST(VmSub, NestedCallStopsAllTasksWhenTheOuterSubReturns) {
  // task 0 calls sub 0, which calls sub 1: sub 1 returns into sub 0, and when
  // sub 0 returns there is no return address left: every task stops.
  auto img = image({{0, code({start(1), call(0), set(5, 1)})}, {1, code({wait(100), set(6, 1)})}},
                   {{0, code({call(1), set(3, 1)})}, {1, set(2, 1)}});
  auto m = run(img);
  EXPECT_EQ(var(m, 2), 1);
  EXPECT_EQ(var(m, 3), 1);
  EXPECT_EQ(var(m, 5), 0);
  EXPECT_EQ(var(m, 6), 0);  // task 1 was stopped too
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_LT(m.now_us(), 100 * rcx::kMicrosPerMs);
}

TEST(VmSub, EachTaskHasItsOwnReturnAddress) {
  auto img = image({{0, code({start(1), call(0), add(1, 1)})}, {1, code({call(0), add(2, 1)})}},
                   {{0, code({wait(1), add(0, 1)})}});
  auto m = run(img);
  EXPECT_EQ(var(m, 0), 2);
  EXPECT_EQ(var(m, 1), 1);
  EXPECT_EQ(var(m, 2), 1);
}

// ---------------------------------------------------------------- tasks

TEST(VmTask, StartOfRunningTaskRestartsIt) {
  auto img = image({{0, code({start(1), wait(5), start(1), wait(500)})}, {1, code({add(0, 1), wait(100), add(1, 1)})}});
  auto m = run(img);
  EXPECT_EQ(var(m, 0), 2);
  EXPECT_EQ(var(m, 1), 1);
  int starts = 0;
  for (const auto& e : events_of(m, rcx::EventKind::TaskStart)) starts += e.index == 1;
  EXPECT_EQ(starts, 2);
}

TEST(VmTask, StartOfUndefinedTaskDoesNothing) {
  auto m = run_task(code({start(5), set(0, 1)}));
  EXPECT_EQ(var(m, 0), 1);
  for (const auto& e : events_of(m, rcx::EventKind::TaskStart)) EXPECT_EQ(e.index, 0);
}

TEST(VmTask, StopTask) {
  auto m = run(image({{0, code({start(1), wait(10), stop(1), wait(200)})}, {1, code({wait(100), set(0, 1)})}}));
  EXPECT_EQ(var(m, 0), 0);
}

TEST(VmTask, StopAllStopsEveryTaskIncludingTheCaller) {
  auto m = run(image({{0, code({start(1), stopall(), set(0, 1)})}, {1, code({wait(10), set(1, 1)})}}));
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(var(m, 1), 0);
}

TEST(VmTask, DeletingARunningTaskStopsAllTasks) {
  auto m = run(image({{0, code({start(1), wait(1), deltask(1), set(0, 1)})}, {1, code({wait(100), set(1, 1)})}}));
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_FALSE(m.slot(0).tasks[1].has_value());
}

TEST(VmTask, DeletingASubStopsTheTaskRunningIt) {
  auto img = image({{0, code({start(1), wait(5), delsub(0), set(0, 1)})}, {1, call(0)}}, {{0, code({wait(100), set(1, 1)})}});
  auto m = run(img);
  EXPECT_EQ(var(m, 0), 1);
  EXPECT_EQ(var(m, 1), 0);
}

// Sub 0 called sub 1, so the task's one return address points into sub 0:
// sub 0 is still being executed, and deleting it stops the task at once
// (seed, Delete subroutine) rather than letting sub 1 finish and return into
// code that is gone, or into whatever a new download put there.
TEST(VmTask, DeletingTheSubAnInnerSubReturnsIntoStopsTheTask) {
  auto img = image({{0, code({start(1), wait(5), delsub(0), set(0, 1)})}, {1, call(0)}},
                   {{0, code({call(1), set(2, 1)})}, {1, code({wait(100), set(1, 1)})}});
  auto m = run(img);
  EXPECT_EQ(var(m, 0), 1);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_EQ(var(m, 2), 0);
  EXPECT_FALSE(m.task(1).active);
}

TEST(VmTask, ReplacingTheSubAnInnerSubReturnsIntoStopsTheTask) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, call(0)}}, {{0, code({call(1), set(2, 1)})}, {1, code({wait(100), set(1, 1)})}}));
  m.start_program();
  m.run_until(10 * rcx::kMicrosPerMs);
  ASSERT_EQ(m.task(0).sub, 1);
  Bytes replacement = code({set(3, 3), set(3, 4), set(3, 5)});  // sub 0's return address lands inside these
  ASSERT_EQ(m.begin_sub_download(0, static_cast<int>(replacement.size())), rcx::DownloadStatus::Ok);
  ASSERT_TRUE(m.write_download(replacement));
  m.end_download();
  m.run(5000 * rcx::kMicrosPerMs);
  EXPECT_EQ(var(m, 1), 0);
  EXPECT_EQ(var(m, 3), 0);
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
}

TEST(VmTask, ReturnInATaskBodyEndsTheTask) {
  auto m = run_task(code({ret(), set(0, 1)}));
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
}

TEST(VmTask, SetProgramNumberStopsAndSwitches) {
  auto m = run_task(code({program(3), set(0, 1)}));
  EXPECT_EQ(m.program(), 3);
  EXPECT_EQ(var(m, 0), 0);
}

// ---------------------------------------------------------------- wait

TEST(VmWait, WaitIsInHundredthsOfASecond) {
  auto m = run_task(code({wait(100), out(0x81)}));
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].t_us, 1'000'000);  // the wait ran at 0 ms
}

TEST(VmWait, WaitFromAVariable) {
  auto m = run_task(code({set(0, 50), waitv(VAR, 0), out(0x81)}));
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].t_us, 501'000);  // wait at 1 ms + 500 ms
}

// ---------------------------------------------------------------- outputs

TEST(VmOutput, OnOffFloatBits) {
  auto m = run_task(code({out(0x81), out(0x42), out(0x04), out(0xc4)}));
  const auto& o = m.state().outputs;
  EXPECT_EQ(o[0].mode, rcx::OutputMode::On);
  EXPECT_EQ(o[1].mode, rcx::OutputMode::Off);
  EXPECT_EQ(o[2].mode, rcx::OutputMode::On);  // both bits set: on
  auto m2 = run_task(code({out(0x87), out(0x04)}));
  EXPECT_EQ(m2.state().outputs[2].mode, rcx::OutputMode::Float);  // neither bit: float
  EXPECT_EQ(m2.state().outputs[0].mode, rcx::OutputMode::On);
}

TEST(VmOutput, DirectionForwardReverseFlip) {
  auto m = run_task(code({dir(0x02), dir(0x44), dir(0x81)}));
  const auto& o = m.state().outputs;
  EXPECT_EQ(o[0].dir, rcx::Direction::Forward);
  EXPECT_EQ(o[1].dir, rcx::Direction::Reverse);
  EXPECT_EQ(o[2].dir, rcx::Direction::Reverse);  // flipped from forward
  auto m2 = run_task(code({dir(0xc4), dir(0xc4), dir(0xc1)}));
  EXPECT_EQ(m2.state().outputs[2].dir, rcx::Direction::Forward);  // both bits: flip, twice
  EXPECT_EQ(m2.state().outputs[0].dir, rcx::Direction::Reverse);
}

TEST(VmOutput, PowerZeroToSevenOthersIgnored) {
  auto m = run_task(code({pwr(0x07, IMM, 3), pwr(0x01, IMM, 8), set(0, -1), pwr(0x02, VAR, 0), pwr(0x04, IMM, 0)}));
  const auto& o = m.state().outputs;
  EXPECT_EQ(o[0].power, 3);
  EXPECT_EQ(o[1].power, 3);
  EXPECT_EQ(o[2].power, 0);
}

TEST(VmOutput, EventsOnlyForChanges) {
  auto m = run_task(code({out(0x81), out(0x81), dir(0x81)}));
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].index, 0);
  EXPECT_EQ(outs[0].output.mode, rcx::OutputMode::On);
}

// ---------------------------------------------------------------- sound, display, messages

TEST(VmSound, SoundsAreQueuedAndPlayOneAfterAnother) {
  auto m = run_task(code({sound(1), sound(2), tone(440, 50)}));
  auto& ev = m.state().events;
  std::vector<rcx::Event> played;
  for (const auto& e : ev)
    if (e.kind == rcx::EventKind::Sound || e.kind == rcx::EventKind::Tone) played.push_back(e);
  ASSERT_EQ(played.size(), 3u);
  EXPECT_EQ(played[0].value, 1);
  EXPECT_EQ(played[0].t_us, 0);
  EXPECT_EQ(played[1].value, 2);
  EXPECT_EQ(played[1].t_us, 300'000);  // after sound 1 (0.30 s)
  EXPECT_EQ(played[2].kind, rcx::EventKind::Tone);
  EXPECT_EQ(played[2].value, 440);
  EXPECT_EQ(played[2].duration, 50);
  EXPECT_EQ(played[2].t_us, 800'000);  // after sound 2 (0.50 s)
}

TEST(VmSound, FullQueueDropsAndBadSoundIgnored) {
  Bytes c;
  for (int i = 0; i < 12; ++i) c = code({c, sound(0)});
  c = code({c, sound(6)});
  auto m = run_task(c);
  EXPECT_EQ(events_of(m, rcx::EventKind::Sound).size(), 9u);  // one playing + 8 queued
}

TEST(VmDisplay, SetDisplayDevices0To6) {
  auto m = run_task(code({display(IMM, 3), display(IMM, 7), set(0, 5), display(VAR, 0)}));
  auto ev = events_of(m, rcx::EventKind::Display);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].value, 3);
  EXPECT_EQ(ev[1].value, 5);
  EXPECT_EQ(m.state().display, 5);
}

TEST(VmMessage, SendSetClear) {
  auto m = run_task(code({set(0, 300), msgsend(VAR, 0), msgset(9), setv(1, MESSAGE, 0), msgclr(), setv(2, MESSAGE, 0)}));
  auto sent = events_of(m, rcx::EventKind::MessageSent);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].value, 300 & 0xff);
  EXPECT_EQ(var(m, 1), 9);
  EXPECT_EQ(var(m, 2), 0);
}

// ---------------------------------------------------------------- datalog

TEST(VmDatalog, FullDatalogIsLeftUnchanged) {
  auto m = run_task(code({logsize(2), set(0, 11), lognext(VAR, 0), set(0, 22), lognext(VAR, 0), set(0, 33), lognext(VAR, 0)}));
  const auto& log = m.state().datalog;
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0].value, 11);
  EXPECT_EQ(log[1].value, 22);
  EXPECT_EQ(events_of(m, rcx::EventKind::Datalog).size(), 2u);
}

TEST(VmDatalog, EntryTypesBySource) {
  auto m = run_task(code({logsize(4), set(5, 1), lognext(VAR, 5), lognext(TIMER, 1), lognext(SENSOR, 2), lognext(CLOCK, 0)}));
  const auto& log = m.state().datalog;
  ASSERT_EQ(log.size(), 4u);
  EXPECT_EQ(log[0].type, 0x05);
  EXPECT_EQ(log[1].type, 0x21);
  EXPECT_EQ(log[2].type, 0x42);
  EXPECT_EQ(log[3].type, 0x80);
}

TEST(VmDatalog, TimerEntriesHoldTenths) {
  // wait at 1 ms until 2501 ms: timer 1 (from power-on) reads 25 tenths.
  auto m = run_task(code({logsize(1), wait(250), lognext(TIMER, 1)}));
  const auto& log = m.state().datalog;
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0].type, 0x21);
  EXPECT_EQ(log[0].value, 25);
}

// ---------------------------------------------------------------- power

TEST(VmPower, PowerOffIgnoredWhenDelayIsZero) {
  auto m = run_task(code({sleepdelay(0), poweroff(), set(0, 1)}));
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(var(m, 0), 1);
}

TEST(VmPower, PowerOffStopsTheRun) {
  auto m = run_task(code({sleepdelay(10), poweroff(), set(0, 1)}));
  EXPECT_EQ(m.stop().kind, StopKind::PowerOff);
  EXPECT_EQ(var(m, 0), 0);
}
