// Frontend speed on generated programs: a long program (lines/second, to see
// that time grows linearly with size) and deep nesting (no quadratic or
// recursive blow-up). The stress tests check correctness on the same inputs.
#include <benchmark/benchmark.h>

#include "frontend/frontend.h"
#include "tests/frontend/generated_programs.h"

namespace {

void run_once(benchmark::State& state, const std::string& src) {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  auto program = rcxc::frontend::parse_source("bench.nqc", src, {}, sm, diags);
  if (!program) state.SkipWithError("the generated program did not pass the frontend");
  benchmark::DoNotOptimize(program);
}

void BM_LongProgram(benchmark::State& state) {
  std::string src = rcxc::test::long_program(static_cast<int>(state.range(0)));
  for (auto _ : state) run_once(state, src);
  state.SetItemsProcessed(state.iterations() * state.range(0));  // lines
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(src.size()));
}
BENCHMARK(BM_LongProgram)->Arg(5000)->Arg(10000)->Arg(50000)->Unit(benchmark::kMillisecond);

void BM_DeepNesting(benchmark::State& state) {
  std::string src = rcxc::test::deeply_nested_program(static_cast<int>(state.range(0)));
  for (auto _ : state) run_once(state, src);
  state.SetItemsProcessed(state.iterations() * state.range(0));  // levels
}
BENCHMARK(BM_DeepNesting)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

void BM_StdlibOnly(benchmark::State& state) {
  for (auto _ : state) run_once(state, "task main() { }\n");
}
BENCHMARK(BM_StdlibOnly)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
