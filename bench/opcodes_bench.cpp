// Decoding speed of the opcode table lookup the emulator relies on.
#include <benchmark/benchmark.h>

#include "rcx/opcodes.h"

static void BM_CommandLookup(benchmark::State& state) {
  std::uint8_t code = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(rcx::command_at(code));
    ++code;
  }
}
BENCHMARK(BM_CommandLookup);

BENCHMARK_MAIN();
