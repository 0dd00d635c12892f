// Machine::run with a hold (the debugger's stop before an instruction): a
// run held any number of times and resumed computes what an unheld run
// does, at the same virtual times (`rcxc debug`, docs/editors.md).
#include <gtest/gtest.h>

#include <random>

#include "rcx/opcodes.h"
#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;

namespace {

void expect_same_run(const rcx::Machine& a, const rcx::Machine& b, int round) {
  EXPECT_EQ(a.stop().kind, b.stop().kind) << "round " << round;
  EXPECT_EQ(a.now_us(), b.now_us()) << "round " << round;
  EXPECT_EQ(a.instructions_executed(), b.instructions_executed()) << "round " << round;
  EXPECT_EQ(a.state().vars, b.state().vars) << "round " << round;
  const auto& ea = a.state().events;
  const auto& eb = b.state().events;
  ASSERT_EQ(ea.size(), eb.size()) << "round " << round;
  for (std::size_t i = 0; i < ea.size(); ++i) {
    EXPECT_EQ(ea[i].t_us, eb[i].t_us) << "round " << round << " event " << i;
    EXPECT_EQ(ea[i].kind, eb[i].kind) << "round " << round << " event " << i;
    EXPECT_EQ(ea[i].index, eb[i].index) << "round " << round << " event " << i;
    EXPECT_EQ(ea[i].value, eb[i].value) << "round " << round << " event " << i;
  }
}

}  // namespace

// Two tasks, a subroutine, a loop, waits and a sensor input: held before
// every third instruction, and at each hold before the instruction it was
// held at (the hold sees the task's pc before the instruction runs).
TEST(VmHold, HeldAndResumedRunsAsAnUnheldOne) {
  // task 0: var0 = 5; start task 1; repeat 3 { var0 += 1; call sub 0; wait 2 }
  auto task0 = code({set(0, 5), {0x71, 1}, loops(IMM, 3), loopc(14), add(0, 1), call(0), wait(2), jmp(128 + 14)});
  auto task1 = code({setv(1, SENSOR, 0), add(2, 7), wait(1), setv(3, SENSOR, 0)});
  auto sub0 = code({add(4, 2), out(0x81)});
  auto img = image({{0, task0}, {1, task1}}, {{0, sub0}});
  auto prepare = [&](rcx::Machine& m) {
    ASSERT_FALSE(m.load(0, img));
    m.schedule({5'000, rcx::SensorRawInput{0, 100}});
    m.start_program();
  };
  rcx::Machine plain;
  prepare(plain);
  plain.run(1000 * rcx::kMicrosPerMs);
  ASSERT_EQ(plain.stop().kind, rcx::StopKind::Ended);
  ASSERT_GT(plain.instructions_executed(), 10);

  rcx::Machine held;
  prepare(held);
  int asked = 0, holds = 0;
  int held_task = -1, held_pc = -1;
  rcx::Machine::Hold hold = [&](int task, const rcx::TaskState& t) {
    // The instruction it held at comes back first, from the same task.
    if (held_task >= 0) {
      EXPECT_EQ(task, held_task);
      EXPECT_EQ(t.pc, held_pc);
      held_task = -1;
      return false;
    }
    if (++asked % 3 != 0) return false;
    held_task = task, held_pc = t.pc;
    return true;
  };
  while (held.run(1000 * rcx::kMicrosPerMs, hold).kind == rcx::StopKind::Running) ++holds;
  EXPECT_GT(holds, 5);
  expect_same_run(plain, held, 0);
}

// Random programs of real opcodes (as VmRobustness makes them), held at
// random instructions: the same events, times and variables every time.
TEST(VmHold, RandomProgramsHeldAtRandomRunAsUnheld) {
  std::vector<const rcx::OpcodeInfo*> commands;
  for (const auto& o : rcx::opcodes())
    if (o.is_command() && rcx::command_size(o)) commands.push_back(&o);
  int total_holds = 0;
  for (int round = 0; round < 200; ++round) {
    std::mt19937 rng(static_cast<unsigned>(round));
    auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    auto program = [&] {
      Bytes c;
      for (int i = pick(1, 30); i > 0; --i) {
        const auto& o = *commands[static_cast<std::size_t>(pick(0, static_cast<int>(commands.size()) - 1))];
        c.push_back(o.code);
        for (int k = *rcx::command_size(o) - 1; k > 0; --k) {
          int kind = pick(0, 9);
          c.push_back(static_cast<std::uint8_t>(kind < 5 ? pick(0, 2) : kind < 7 ? pick(0, 15) : pick(0, 255)));
        }
      }
      return c;
    };
    rcx::Image img;
    for (int t = pick(1, 10) - 1; t >= 0; --t) img.fragments.push_back({rcx::FragmentType::Task, static_cast<std::uint8_t>(t), program()});
    for (int s = pick(0, 8) - 1; s >= 0; --s) img.fragments.push_back({rcx::FragmentType::Subroutine, static_cast<std::uint8_t>(s), program()});
    std::vector<rcx::TimedInput> inputs;
    for (int i = 0; i < 4; ++i) inputs.push_back({pick(0, 3000) * rcx::kMicrosPerMs, rcx::SensorRawInput{pick(0, 2), pick(0, 1023)}});
    auto prepare = [&](rcx::Machine& m) {
      m.load(0, img);
      for (const auto& in : inputs) m.schedule(in);
      m.start_program();
    };
    rcx::Config config = ms_config();
    config.seed = static_cast<std::uint64_t>(round);
    const rcx::Micros limit = 3000 * rcx::kMicrosPerMs;
    rcx::Machine plain(config), held(config);
    prepare(plain);
    prepare(held);
    plain.run(limit);
    bool pass_next = false;
    int every = pick(1, 7);
    std::int64_t asked = 0;
    rcx::Machine::Hold hold = [&](int, const rcx::TaskState&) {
      if (pass_next) return pass_next = false;
      return pass_next = ++asked % every == 0;
    };
    while (held.run(limit, hold).kind == rcx::StopKind::Running) ++total_holds;
    expect_same_run(plain, held, round);
  }
  EXPECT_GT(total_holds, 1000);
}
