// Emulator throughput: bytecode instructions executed per wall-clock second.
// The instruction cost is set to 1 µs of virtual time so that running to
// virtual time T executes exactly T instructions.
#include <benchmark/benchmark.h>

#include "runtime/vm.h"

namespace {

rcx::Image one_task(std::vector<std::uint8_t> code) {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, std::move(code)});
  return img;
}

void run_loop(benchmark::State& state, const rcx::Image& image) {
  constexpr rcx::Micros kInstructions = 1'000'000;
  rcx::Config config;
  config.instruction_cost_us = 1;
  std::int64_t executed = 0;
  for (auto _ : state) {
    rcx::Machine m(config);
    m.load(0, image);
    m.start_program();
    m.run_until(kInstructions);
    benchmark::DoNotOptimize(m.state().vars[0]);
    executed += kInstructions;
  }
  state.SetItemsProcessed(executed);
}

// add var0, 1; jmp back: the tightest possible loop.
void BM_TightLoop(benchmark::State& state) {
  run_loop(state, one_task({0x24, 0x00, 0x02, 0x01, 0x00, 0x27, 0x80 + 6}));  // 6 - 134 + 128 = 0
}
BENCHMARK(BM_TightLoop)->Unit(benchmark::kMillisecond);

// A counting loop with a test-and-branch and a sensor read, closer to real programs.
void BM_TestAndBranchLoop(benchmark::State& state) {
  // 0 add var0; 5 set var1 = sensor 0; 10 chk var0 != var2 -> 0 (16 - 16); 17 set var0 = 0; 22 jmp -> 0
  run_loop(state, one_task({0x24, 0x00, 0x02, 0x01, 0x00, 0x14, 0x01, 0x09, 0x00, 0x00, 0x85, 0x80, 0x00, 0x00,
                            0x00, 0x02, 0xf0, 0x14, 0x00, 0x02, 0x00, 0x00, 0x27, 0x80 + 23 - 0}));
}
BENCHMARK(BM_TestAndBranchLoop)->Unit(benchmark::kMillisecond);

// Ten tasks sharing the processor round-robin.
void BM_TenTasks(benchmark::State& state) {
  rcx::Image img;
  for (std::uint8_t t = 0; t < 10; ++t)
    img.fragments.push_back({rcx::FragmentType::Task, t, {0x24, t, 0x02, 0x01, 0x00, 0x27, 0x80 + 6}});
  // task 0 starts the others first
  img.fragments[0].code = {0x71, 1, 0x71, 2, 0x71, 3, 0x71, 4, 0x71, 5, 0x71, 6, 0x71, 7, 0x71, 8, 0x71, 9,
                           0x24, 0x00, 0x02, 0x01, 0x00, 0x27, 0x80 + 6};
  run_loop(state, img);
}
BENCHMARK(BM_TenTasks)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
