// Whatever bytes a program or a host sends, the machine answers with a state,
// a fault or a refusal: never a crash, a hang or an out-of-range access.
// (Seeded, so every run checks the same inputs.)
#include <gtest/gtest.h>

#include <random>

#include "rcx/opcodes.h"
#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;

TEST(VmRobustness, RandomBytecodeRunsOrFaults) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> byte(0, 255), length(1, 64);
  int faults = 0;
  for (int round = 0; round < 2000; ++round) {
    Bytes task0(static_cast<std::size_t>(length(rng))), task1(static_cast<std::size_t>(length(rng)));
    Bytes sub0(static_cast<std::size_t>(length(rng)));
    for (auto* c : {&task0, &task1, &sub0})
      for (auto& b : *c) b = static_cast<std::uint8_t>(byte(rng));
    auto m = run(image({{0, task0}, {1, task1}}, {{0, sub0}}), 2000);
    EXPECT_NE(m.stop().kind, rcx::StopKind::Running);
    EXPECT_LE(m.now_us(), 2000 * rcx::kMicrosPerMs);
    if (m.stop().kind == rcx::StopKind::Fault) {
      ++faults;
      ASSERT_TRUE(m.stop().fault);
      EXPECT_GE(m.stop().fault->address, 0);
    }
  }
  EXPECT_GT(faults, 1000);  // random bytes are mostly not valid code
}

// Random bytes mostly fault at the first byte; programs made of real opcodes
// with random operands (mostly small, so sources and indices are often legal)
// reach calls, loops, deletes, program switches, the datalog and the sound
// queue, in five slots, run in one go or in small steps with direct commands
// and task starts in between.
TEST(VmRobustness, RandomProgramsOfRealOpcodesRunOrFault) {
  std::vector<const rcx::OpcodeInfo*> commands;
  for (const auto& o : rcx::opcodes())
    if (o.is_command() && rcx::command_size(o)) commands.push_back(&o);
  int ended = 0;
  for (int round = 0; round < 400; ++round) {
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
    rcx::Config config = ms_config();
    config.seed = static_cast<std::uint64_t>(round);
    rcx::Machine m(config);
    for (int slot = 0; slot < rcx::kPrograms; ++slot) {
      rcx::Image img;
      for (int t = pick(1, 10) - 1; t >= 0; --t) img.fragments.push_back({rcx::FragmentType::Task, static_cast<std::uint8_t>(t), program()});
      for (int s = pick(0, 8) - 1; s >= 0; --s) img.fragments.push_back({rcx::FragmentType::Subroutine, static_cast<std::uint8_t>(s), program()});
      EXPECT_FALSE(m.load(slot, img).has_value());
    }
    for (int i = 0; i < 6; ++i) {
      rcx::Micros at = pick(0, 3000) * rcx::kMicrosPerMs;
      m.schedule({at, rcx::SensorRawInput{pick(0, 2), pick(0, 1023)}});
      m.schedule({at, rcx::MessageInput{pick(0, 255)}});
    }
    m.start_program();
    const rcx::Micros limit = 3000 * rcx::kMicrosPerMs;
    if (round % 2 == 0) {
      m.run(limit);
    } else {
      for (rcx::Micros t = 0; t < limit; t += pick(1, 50'000)) {
        m.run_until(t);
        if (pick(0, 20) == 0) {
          Bytes request{static_cast<std::uint8_t>(pick(0, 255))};
          for (int j = pick(0, 6); j > 0; --j) request.push_back(static_cast<std::uint8_t>(pick(0, 255)));
          m.execute_direct(request);
        }
        if (pick(0, 50) == 0) m.start_task(pick(0, 9));
      }
      m.run_until(limit);
    }
    // run() always ends in a stop; run_until() leaves a brick with active tasks running.
    if (m.stop().kind == rcx::StopKind::Running) {
      EXPECT_TRUE(round % 2 == 1 && m.any_task_active());
    }
    EXPECT_LE(m.now_us(), limit);
    for (std::size_t i = 1; i < m.state().events.size(); ++i)
      ASSERT_LE(m.state().events[i - 1].t_us, m.state().events[i].t_us) << "round " << round;
    if (m.stop().kind == rcx::StopKind::Ended) ++ended;
  }
  EXPECT_GT(ended, 50);  // many programs are valid all the way through
}

TEST(VmRobustness, RandomDirectCommandsAreAnsweredOrRefused) {
  std::mt19937 rng(777);
  std::uniform_int_distribution<int> byte(0, 255), length(0, 8);
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({add(0, 1), jmp(0x80 + 6)})}}));  // loops: 6 - 134 + 128 = 0
  m.start_program();
  int answered = 0;
  for (int round = 0; round < 20000; ++round) {
    Bytes request(static_cast<std::size_t>(length(rng)));
    for (auto& b : request) b = static_cast<std::uint8_t>(byte(rng));
    auto reply = m.execute_direct(request);
    if (reply.ok) ++answered;
    else EXPECT_FALSE(reply.error.empty());
    if (round % 100 == 0) m.run_until(m.now_us() + 5 * rcx::kMicrosPerMs);
  }
  EXPECT_GT(answered, 100);
}

TEST(VmRobustness, HostOperationsRejectOutOfRangeArguments) {
  rcx::Machine m;
  m.start_task(-1);
  m.start_task(10);
  m.stop_task(99);
  m.delete_task(-3);
  m.delete_sub(8);
  m.select_program(5);
  EXPECT_EQ(m.program(), 0);
  EXPECT_EQ(m.get_value(0, 32), 0);
  EXPECT_EQ(m.get_value(9, 3), 0);
  EXPECT_EQ(m.get_value(1, 4), 0);
  EXPECT_EQ(m.get_value(3, -1), 0);
  EXPECT_EQ(m.get_value(99, 0), 0);
  EXPECT_EQ(m.sensor_value(7), 0);
  EXPECT_TRUE(m.upload_datalog(-1, 1).empty());
  EXPECT_FALSE(m.set_datalog_size(-1));
  EXPECT_TRUE(m.load(5, rcx::Image{}).has_value());
  EXPECT_FALSE(m.any_task_active());
}

// A program that switches output A on every pass: out A on, out A off, jmp.
// Three instructions a pass make two output events.
namespace {
rcx::Image toggling_image() {
  using namespace vmtest;
  return image({{0, code({out(0x81), out(0x41), jmp(0x80 | 5)})}});
}
}  // namespace

TEST(VmRobustness, ARunStopsWhenItsEventLogIsFull) {
  rcx::Config config = vmtest::ms_config();
  config.event_limit = 100;
  rcx::Machine m = vmtest::run(toggling_image(), 10'000, config);
  EXPECT_EQ(m.stop().kind, rcx::StopKind::EventLimit);
  EXPECT_EQ(m.state().events.size(), 100u);
  // The task's start is the first event, then two a pass: the 100th is the
  // 'on' of pass 50 (its 148th instruction), and the 'off' after it, the
  // 149th instruction at 1 ms each, found the log full.
  EXPECT_EQ(m.now_us(), 149 * rcx::kMicrosPerMs);
  EXPECT_STREQ(rcx::to_string(m.stop().kind), "event_limit");
  EXPECT_EQ(rcx::event_limit_reason(m), "it recorded 100 events, the most a run keeps");
  // A stopped run stays stopped: running on records nothing more.
  m.run_until(20'000 * rcx::kMicrosPerMs);
  EXPECT_EQ(m.stop().kind, rcx::StopKind::EventLimit);
  EXPECT_EQ(m.state().events.size(), 100u);
}

TEST(VmRobustness, AHostThatForgetsEventsRunsOnPastTheLimit) {
  rcx::Config config = vmtest::ms_config();
  config.event_limit = 100;
  rcx::Machine m(config);
  ASSERT_FALSE(m.load(0, toggling_image()).has_value());
  m.start_program();
  for (int second = 1; second <= 10; ++second) {
    m.run_until(second * 30 * rcx::kMicrosPerMs);  // 10 passes, 20 events each time
    EXPECT_EQ(m.stop().kind, rcx::StopKind::Running) << second;
    m.forget_events();
  }
  EXPECT_TRUE(m.state().events.empty());
  EXPECT_EQ(m.now_us(), 300 * rcx::kMicrosPerMs);
}
