// Compiler speed on generated programs: many loops and tests (the passes
// that reorder blocks), many inline calls (each copy has its own
// variables), many statements whose expressions branch (data-flow over
// a long chain of joins), one very long expression (lowering asks
// about each subexpression at every level) and written-out steps, runs of
// which become loops (rerolling splits one block many times), and many
// calls of one subroutine (absorption looks at every call). Time and memory must grow linearly: items/second
// roughly the same at every size. Programs this long are too big for the
// brick, so a run may end in the size diagnostic, after every pass.
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

std::string many_inline_calls(int n) {
  std::string src = "int x, y;\nvoid f(int a, int &r) { r = r + a; if (r > 100) r = 0; }\ntask main() {\n";
  for (int i = 0; i < n; ++i) src += "  f(" + std::to_string(i) + ", x); f(y, y);\n";
  return src + "}\n";
}

std::string many_branching_expressions(int n) {
  std::string src = "int x;\ntask main() {\n";
  for (int i = 0; i < n; ++i) src += "  x = x * 3 + (x / 7) % 5 - (x > " + std::to_string(i) + ") + (x ? 1 : 2);\n";
  return src + "}\n";
}

// One statement: x = x + x + ... (n terms), a left-deep expression.
std::string long_expression(int n) {
  std::string src = "int x;\ntask main() {\n  x = x";
  for (int i = 1; i < n; ++i) src += " + x";
  return src + ";\n}\n";
}

// `n` additions whose constants step by 3 in runs of 7: n / 7 loops.
std::string written_out_steps(int n) {
  std::string src = "int x;\ntask main() {\n";
  for (int i = 0; i < n; ++i) src += "  x += " + std::to_string(i % 7 * 3 + i / 7 % 5) + ";\n";
  return src + "}\n";
}

// Loops three deep that merge into one counter loop each
// (ir/nested_repeat.cpp): the pass must not search every pair per merge.
std::string nested_repeats(int n) {
  std::string src = "int x;\ntask main() {\n";
  for (int i = 0; i < n; ++i) src += "  repeat (2) repeat (3) repeat (2) x++;\n";
  return src + "}\n";
}

// `n` calls of one subroutine, each after a wait of 1, 2 or 3 tenths and
// before the same addition: what the calls share moves into the
// subroutine (backend/absorb.cpp), which looks at every call per move.
std::string many_sub_calls(int n) {
  std::string src = "int x;\nsub s() { PlaySound(1); Wait(2); PlaySound(2); }\ntask main() {\n";
  for (int i = 0; i < n; ++i) src += "  Wait(" + std::to_string(i % 3 * 10 + 10) + "); s(); x += 1;\n";
  return src + "}\n";
}

void compile(benchmark::State& state, const std::string& src) {
  for (auto _ : state) {
    rcxc::SourceManager sm;
    rcxc::Diagnostics diags;
    rcxc::ir::Log log;
    auto out = rcxc::backend::compile_source("bench.nqc", src, {}, rcxc::ir::OptLevel::Os, sm, diags, log);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_ManyLoops(benchmark::State& state) { compile(state, many_loops(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_ManyLoops)->Arg(1000)->Arg(4000)->Arg(16000)->Unit(benchmark::kMillisecond);

void BM_ManyInlineCalls(benchmark::State& state) {
  compile(state, many_inline_calls(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_ManyInlineCalls)->Arg(1000)->Arg(4000)->Arg(16000)->Unit(benchmark::kMillisecond);

void BM_ManyBranchingExpressions(benchmark::State& state) {
  compile(state, many_branching_expressions(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_ManyBranchingExpressions)->Arg(250)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond);

void BM_LongExpression(benchmark::State& state) { compile(state, long_expression(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_LongExpression)->Arg(1000)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond);

void BM_WrittenOutSteps(benchmark::State& state) { compile(state, written_out_steps(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_WrittenOutSteps)->Arg(1000)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond);

void BM_NestedRepeats(benchmark::State& state) { compile(state, nested_repeats(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_NestedRepeats)->Arg(500)->Arg(3000)->Unit(benchmark::kMillisecond);

void BM_ManySubCalls(benchmark::State& state) { compile(state, many_sub_calls(static_cast<int>(state.range(0)))); }
BENCHMARK(BM_ManySubCalls)->Arg(1000)->Arg(4000)->Arg(16000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
