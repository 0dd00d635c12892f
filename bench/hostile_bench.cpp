// The hostile inputs of issue 21 (tests/cli/hostile_input_test.cpp checks
// that each ends with its error and under 100 MB): each must end within a
// second; and loop nests with a local per level, which once took a minute at
// 1000 levels in the liveness analysis, must grow with the size of the
// answer, not with a power of the depth.
#include <benchmark/benchmark.h>

#include <string>

#include "backend/compile.h"

namespace {

std::string repeat(const std::string& s, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

void compile_once(const std::string& src) {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  rcxc::ir::Log log;
  auto out = rcxc::backend::compile_source("bench.nqc", src, {}, rcxc::ir::OptLevel::O2, sm, diags, log);
  benchmark::DoNotOptimize(out);
}

void BM_Hostile(benchmark::State& state, const std::string& src) {
  for (auto _ : state) compile_once(src);
}
BENCHMARK_CAPTURE(BM_Hostile, blocks_70000, "task main() {" + repeat("{", 70000) + repeat("}", 70000) + "}\n")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hostile, prefix_100000, "int x; task main() { x = " + repeat("- ", 100000) + "x; }\n")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hostile, sum_200000, "int x; task main() { x = x" + repeat("+x", 199999) + "; }\n")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hostile, ifs_100000, "int x; task main() { " + repeat("if (x) ", 100000) + "x = 1; }\n")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hostile, assignments_100000, "int x; task main() { " + repeat("x = ", 100000) + "1; }\n")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hostile, hash_if_100000,
                  "#if " + repeat("(", 100000) + "1" + repeat(")", 100000) + "\n#endif\ntask main() {}\n")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Hostile, macro_calls_10000,
                  "#define F(x) x\nint y; task main() { y = " + repeat("F(", 10000) + "1" + repeat(")", 10000) + "; }\n")
    ->Unit(benchmark::kMillisecond);

// Levels of `for (int i ...)`: past 32 the locals do not fit the RCX's
// slots, but every pass before slot allocation runs.
void BM_NestedLoopsWithLocals(benchmark::State& state) {
  int depth = static_cast<int>(state.range(0));
  std::string src = "int x;\ntask main()\n{\n" + repeat("for (int i = 0; i < 2; i++)\n{\n", depth) + "x = x + 1;\n" +
                    repeat("}\n", depth) + "}\n";
  for (auto _ : state) compile_once(src);
  state.SetItemsProcessed(state.iterations() * depth);  // levels
}
BENCHMARK(BM_NestedLoopsWithLocals)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
