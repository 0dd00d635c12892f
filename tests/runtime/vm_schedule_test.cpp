// Scheduling and timing: round-robin one instruction per turn, the fixed
// instruction cost, idle jumps, time limits, and exact incremental advancing.
#include <gtest/gtest.h>

#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;
using rcx::kMicrosPerMs;
using rcx::StopKind;

TEST(VmSchedule, TasksTakeTurnsOneInstructionEach) {
  // t=0 task 0 starts task 1; t=1 ms task 1 turns B on; t=2 ms task 0 turns A on.
  auto m = run(image({{0, code({start(1), out(0x81)})}, {1, out(0x82)}}));
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 2u);
  EXPECT_EQ(outs[0].index, 1);
  EXPECT_EQ(outs[0].t_us, 1 * kMicrosPerMs);
  EXPECT_EQ(outs[1].index, 0);
  EXPECT_EQ(outs[1].t_us, 2 * kMicrosPerMs);
}

TEST(VmSchedule, DefaultCostIsTwoMillisecondsPerInstruction) {
  rcx::Machine m;  // default config
  m.load(0, image({{0, code({set(0, 1), set(0, 2), out(0x81)})}}));
  m.start_program();
  m.run(1000 * kMicrosPerMs);
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].t_us, 4 * kMicrosPerMs);
  EXPECT_EQ(m.now_us(), 6 * kMicrosPerMs);  // ended after the third instruction
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
}

TEST(VmSchedule, CostIsConfigurable) {
  rcx::Config c;
  c.instruction_cost_us = 250;
  auto m = run(image({{0, code({set(0, 1), set(0, 2), out(0x81)})}}), 1000, c);
  EXPECT_EQ(events_of(m, rcx::EventKind::Output).at(0).t_us, 500);
}

TEST(VmSchedule, InfiniteLoopStopsAtTheTimeLimit) {
  auto m = run_task(jmp(0x81), 1000);  // 1 - 0x81 + 128 = 0: jump to itself
  EXPECT_EQ(m.stop().kind, StopKind::TimeLimit);
  EXPECT_EQ(m.now_us(), 1000 * kMicrosPerMs);
}

TEST(VmSchedule, WaitingTasksCostNothingAndTimeJumps) {
  auto m = run_task(wait(30000), 10'000);  // 300 s wait, 10 s limit
  EXPECT_EQ(m.stop().kind, StopKind::TimeLimit);
  EXPECT_EQ(m.now_us(), 10'000 * kMicrosPerMs);
}

// `rcxc run --instruction-us 1000000 --for 10` said "time_limit at 1000 ms",
// and the inputs of the run's first 10 ms showed at 1000 ms: the run went on
// to the end of the instruction that began before the limit. It stops at the
// limit; that instruction's effects, dated at its start, are in.
TEST(VmSchedule, ARunStopsAtItsLimitThoughAnInstructionLastsLonger) {
  rcx::Config c;
  c.instruction_cost_us = 1'000'000;
  rcx::Machine m(c);
  m.load(0, image({{0, code({out(0x81), out(0x82)})}}));
  m.schedule({5 * kMicrosPerMs, rcx::MessageInput{3}});
  m.start_program();
  m.run(10 * kMicrosPerMs);
  EXPECT_EQ(m.stop().kind, StopKind::TimeLimit);
  EXPECT_EQ(m.now_us(), 10 * kMicrosPerMs);
  auto outs = events_of(m, rcx::EventKind::Output);
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].t_us, 0);
  for (const auto& e : m.state().events) EXPECT_LE(e.t_us, 10 * kMicrosPerMs) << static_cast<int>(e.kind);
  // A program whose one instruction is still going at the limit has not ended.
  auto one = run(image({{0, out(0x81)}}), 10, c);
  EXPECT_EQ(one.stop().kind, StopKind::TimeLimit);
  EXPECT_EQ(one.now_us(), 10 * kMicrosPerMs);
  // Given the time, it ends (running off the end of the task at 1000 ms
  // costs nothing).
  auto exact = run(image({{0, out(0x81)}}), 1001, c);
  EXPECT_EQ(exact.stop().kind, StopKind::Ended);
  EXPECT_EQ(exact.now_us(), 1000 * kMicrosPerMs);
}

TEST(VmSchedule, EndsWhenNoTaskIsActive) {
  auto m = run_task(set(0, 1));
  EXPECT_EQ(m.stop().kind, StopKind::Ended);
  EXPECT_EQ(m.now_us(), 1 * kMicrosPerMs);
  auto stops = events_of(m, rcx::EventKind::TaskStop);
  ASSERT_EQ(stops.size(), 1u);
  EXPECT_EQ(stops[0].t_us, 1 * kMicrosPerMs);
}

TEST(VmSchedule, InputsApplyAtTheirTime) {
  rcx::Machine m(ms_config());
  m.schedule({250 * kMicrosPerMs, rcx::SensorRawInput{1, 10}});
  m.schedule({100 * kMicrosPerMs, rcx::SensorRawInput{1, 20}});
  m.run_until(99 * kMicrosPerMs);
  EXPECT_EQ(m.state().sensors[1].raw, 1023);
  m.run_until(100 * kMicrosPerMs);
  EXPECT_EQ(m.state().sensors[1].raw, 20);
  m.run_until(300 * kMicrosPerMs);
  EXPECT_EQ(m.state().sensors[1].raw, 10);
}

namespace {

rcx::Image busy_program() {
  // Two tasks, waits, sounds, sensor reads and a loop.
  // Task 0: 2 loops 20; 5 loopc -> 25 (6 + 19); ...; 23 jmp back to 5 (24 - 147 + 128).
  // Task 1: 13 jmp back to 0 (14 - 142 + 128).
  return image({{0, code({start(1), loops(IMM, 20), loopc(19), sound(1), setv(1, SENSOR, 0), add(0, 1), wait(7),
                          jmp(147)})},
                {1, code({add(2, 3), tone(500, 3), wait(13), jmp(142)})}});
}

}  // namespace

TEST(VmSchedule, AdvancingInSmallStepsEqualsOneBigStep) {
  auto img = busy_program();
  rcx::Machine big(ms_config()), small(ms_config());
  for (auto* m : {&big, &small}) {
    m->load(0, img);
    m->schedule({333 * kMicrosPerMs, rcx::SensorRawInput{0, 100}});
    m->schedule({777 * kMicrosPerMs, rcx::MessageInput{5}});
    m->start_program();
  }
  big.run_until(3000 * kMicrosPerMs);
  for (rcx::Micros t = 0; t <= 3000 * kMicrosPerMs; t += 7 * kMicrosPerMs + 123) small.run_until(t);
  small.run_until(3000 * kMicrosPerMs);
  EXPECT_EQ(big.now_us(), small.now_us());
  EXPECT_EQ(big.state().vars, small.state().vars);
  ASSERT_EQ(big.state().events.size(), small.state().events.size());
  for (std::size_t i = 0; i < big.state().events.size(); ++i) {
    EXPECT_EQ(big.state().events[i].t_us, small.state().events[i].t_us) << i;
    EXPECT_EQ(big.state().events[i].kind, small.state().events[i].kind) << i;
  }
  EXPECT_EQ(big.stop().kind, StopKind::Running);
  EXPECT_EQ(var(big, 0), 20);
}

TEST(VmSchedule, EventsAreInTimeOrder) {
  auto m = run(busy_program(), 3000);
  rcx::Micros last = 0;
  for (const auto& e : m.state().events) {
    EXPECT_GE(e.t_us, last);
    last = e.t_us;
  }
}

TEST(VmSchedule, IdleBrickKeepsTimeForTheLink) {
  rcx::Machine m(ms_config());
  const auto& s = m.run_until(5000 * kMicrosPerMs);
  EXPECT_EQ(s.kind, StopKind::Ended);
  EXPECT_EQ(m.now_us(), 5000 * kMicrosPerMs);
  EXPECT_EQ(m.timer_value(0), 50);  // tenths
}

TEST(VmSchedule, FaultStopsAllTasksAndStartClearsIt) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({start(1), Bytes{0xff}})}, {1, wait(1000)}}));
  m.start_program();
  m.run(100 * kMicrosPerMs);
  ASSERT_EQ(m.stop().kind, StopKind::Fault);
  EXPECT_EQ(m.stop().fault->address, 2);
  EXPECT_FALSE(m.any_task_active());
  m.start_task(1);
  EXPECT_EQ(m.stop().kind, StopKind::Running);
  EXPECT_FALSE(m.stop().fault);
}
