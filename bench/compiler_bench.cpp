// Compiler speed on generated programs with many loops and tests: the
// passes that reorder blocks must stay linear (items/second roughly the
// same at every size). A program this long is too big for the brick, so
// the run ends in the size diagnostic, after every pass has run.
#include <benchmark/benchmark.h>

#include <string>

#include "backend/compile.h"

namespace {

// `n` while loops with two-part tests, then `n` if/else statements whose
// test has no one-instruction negation.
std::string many_loops(int n) {
  std::string src = "int x, y;\ntask main() {\n";
  for (int i = 0; i < n; ++i) src += "  while (x < " + std::to_string(i) + " && y >= x) { x++; }\n";
  for (int i = 0; i < n; ++i) src += "  if (x <= y) { x++; } else { y++; }\n";
  return src + "}\n";
}

void BM_ManyLoops(benchmark::State& state) {
  std::string src = many_loops(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    rcxc::SourceManager sm;
    rcxc::Diagnostics diags;
    rcxc::ir::Log log;
    auto out = rcxc::backend::compile_source("bench.nqc", src, {}, rcxc::ir::OptLevel::Os, sm, diags, log);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));  // loops
}
BENCHMARK(BM_ManyLoops)->Arg(1000)->Arg(4000)->Arg(16000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
