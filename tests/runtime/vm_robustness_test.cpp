// Whatever bytes a program or a host sends, the machine answers with a state,
// a fault or a refusal: never a crash, a hang or an out-of-range access.
// (Seeded, so every run checks the same inputs.)
#include <gtest/gtest.h>

#include <random>

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
