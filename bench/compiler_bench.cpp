// Compiler speed on generated programs: many loops and tests (the passes
// that reorder blocks), many inline calls (each copy has its own
// variables), many statements whose expressions branch (data-flow over
// a long chain of joins), one very long expression (lowering asks
// about each subexpression at every level) and written-out steps, runs of
// which become loops (rerolling splits one block many times), and many
// calls of one subroutine (absorption looks at every call). Time and memory must grow linearly: items/second
// roughly the same at every size. Programs this long are too big for the
// brick, so a run may end in the size diagnostic, after every pass. They
// compile at -Os, which runs every pass (rerolling and outlining too).
//
// Before the benchmarks, a table against nqc in the same run: a program of
// one line, then programs of 100 to 100 000 lines written as people write them (inline functions
// called from tasks, loops, tests, waits, motor commands), each compiled
// by `rcxc compile` and by `nqc -Trcx` as processes, the median CPU time
// of several runs of each (startup, standard library and writing the image
// included). A long program is written as a main file that #includes
// parts, since rcxc reads no source file over 1 MiB.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "backend/compile.h"
#include "bench/corpus.h"

namespace {

using rcxc::bench::children_cpu_seconds;

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

// n subroutines, each called once from main: past the firmware's eight the
// compiler inlines the cheapest, choosing once for all of them (choosing
// again after each took 41 s for 1 000).
std::string many_subroutines(int n) {
  std::string src = "int x, y;\n";
  for (int i = 0; i < n; ++i)
    src += fmt::format("sub s{}() {{ x += {}; if (x > {}) {{ y = x * 2; PlaySound(1); }} OnFwd(OUT_A); Wait({}); }}\n", i,
                       i % 7, i % 13, i % 5 + 1);
  src += "task main() {\n";
  for (int i = 0; i < n; ++i) src += fmt::format("  s{}();\n", i);
  return src + "}\n";
}

// About `lines` lines: half in inline functions of 20 lines (parameters,
// a local, tests, motor commands), each called once, and half in four
// tasks (loops, tests, waits, motor commands, the calls). Too long for the
// brick from a few thousand lines, which both compilers find at the end.
// One string per top-level item (a function, a task, main), in order.
std::vector<std::string> typical_program(int lines) {
  std::vector<std::string> items{"int speed, count, seen;\n"};
  int inlines = std::max(1, lines / 40);
  for (int f = 0; f < inlines; ++f) {
    std::string src = fmt::format("void step{}(int n, int &total) {{\n  int k = n * 2;\n", f);
    for (int i = 0; i < 17; ++i)
      src += fmt::format("  if (k > {}) {{ total += k; OnFwd(OUT_A); }} else {{ total -= {}; Off(OUT_A); }}\n", i, i);
    items.push_back(src + "}\n");
  }
  int next_call = 0;
  for (int t = 0; t < 4; ++t) {
    std::string src = fmt::format("task t{}() {{\n  int local = {};\n  while (true) {{\n", t, t);
    for (int i = 0; i < lines / 8; ++i) {
      if (i % 5 == 1 && next_call < inlines) {
        src += fmt::format("    step{}(local, count);\n", next_call++);
        continue;
      }
      switch (i % 5) {
        case 0: src += fmt::format("    if (SENSOR_1 == 1) {{ OnRev(OUT_A + OUT_C); Wait({}); }}\n", i % 50 * 10 + 10); break;
        case 2: src += fmt::format("    repeat ({}) {{ PlaySound(SOUND_CLICK); local++; }}\n", i % 4 + 2); break;
        case 3: src += "    until (SENSOR_2 > 50 || Timer(0) > 100);\n"; break;
        default: src += fmt::format("    speed = (speed + local * {}) % 8; SetPower(OUT_A, speed);\n", i % 9); break;
      }
    }
    items.push_back(src + "  }\n}\n");
  }
  items.push_back("task main() {\n  SetSensor(SENSOR_1, SENSOR_TOUCH); SetSensor(SENSOR_2, SENSOR_LIGHT);\n"
                  "  start t0; start t1; start t2; start t3;\n}\n");
  return items;
}

// Writes `items` as `main` and files it #includes, each under 512 KB:
// rcxc refuses a source file over 1 MiB (rcx/file_read.h), so a long
// program is several files, as long programs are. Returns the lines.
std::size_t write_program(const std::filesystem::path& main, const std::vector<std::string>& items) {
  std::ofstream out(main);
  std::string part;
  std::size_t lines = 0, parts = 0;
  auto flush = [&] {
    if (part.empty()) return;
    auto name = fmt::format("{}.part{}.nqc", main.stem().string(), parts++);
    std::ofstream(main.parent_path() / name) << part;
    out << "#include \"" << name << "\"\n";
    part.clear();
  };
  for (const auto& item : items) {
    if (part.size() + item.size() > 512 * 1024) flush();
    part += item;
    lines += static_cast<std::size_t>(std::count(item.begin(), item.end(), '\n'));
  }
  flush();
  return lines;
}

double median(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  std::size_t mid = times.size() / 2;
  return times.size() % 2 ? times[mid] : (times[mid - 1] + times[mid]) / 2;
}

// CPU seconds (user + system) of `command` run once as a process; nullopt
// when it cannot be started, or fails and `must_succeed`.
std::optional<double> cpu_of(const std::string& command, bool must_succeed) {
  double before = children_cpu_seconds();
  int status = std::system((command + " >/dev/null 2>&1").c_str());
  if (status == -1 || (must_succeed && status != 0)) return std::nullopt;
  return children_cpu_seconds() - before;
}

// The median CPU seconds of `ours` and of `theirs`, each run `runs` times,
// the two alternating so that a change in the machine's load falls on both
// alike (one after the other, a millisecond-long compile moved by a tenth
// or more between runs of the table); the median, so that a run slowed by
// another process does not move the figure. `theirs` is nullopt when one of
// its runs fails (nqc gives up on some long programs: that size has no
// comparison); `ours` may fail (a program too big for the brick).
std::pair<std::optional<double>, std::optional<double>> median_cpu(const std::string& ours, const std::string& theirs,
                                                                   int runs) {
  std::vector<double> our_times, their_times;
  bool theirs_failed = false;
  for (int r = 0; r < runs; ++r) {
    auto o = cpu_of(ours, false);
    if (!o) return {std::nullopt, std::nullopt};
    our_times.push_back(*o);
    if (theirs_failed) continue;
    auto t = cpu_of(theirs, true);
    if (t) their_times.push_back(*t);
    theirs_failed = !t;
  }
  std::optional<double> their_median;
  if (!theirs_failed) their_median = median(their_times);
  return {median(our_times), their_median};
}

void print_against_nqc(const std::filesystem::path& rcxc) {
  namespace fs = std::filesystem;
  if (std::system("nqc -help >/dev/null 2>&1") == -1 || !fs::exists(rcxc)) return;
  // RCXC_BENCH_PROGRAMS names a folder to write the programs into and keep
  // (to profile one compile by itself); otherwise a temporary one.
  const char* keep = std::getenv("RCXC_BENCH_PROGRAMS");
  std::optional<rcxc::bench::ScratchDir> scratch;
  fs::path dir = keep && *keep ? fs::path(keep) : scratch.emplace("rcxc-compiler-bench").path;
  fs::create_directories(dir);
  std::cout << "CPU time of one compile as a process, median of the runs (ratio: rcxc / nqc)\n";
  std::cout << fmt::format("{:>8} {:>5} {:>12} {:>12} {:>7} {:>14}\n", "lines", "runs", "rcxc ms", "nqc ms", "ratio",
                           "rcxc us/line");
  // One line: start-up and the standard library, most of what a program of
  // the corpus costs.
  for (int lines : {1, 100, 1000, 3000, 10000, 30000, 100000}) {
    fs::path file = dir / fmt::format("typical{}.nqc", lines);
    std::size_t real_lines =
        lines == 1 ? write_program(file, {"task main() { OnFwd(OUT_A); }\n"}) : write_program(file, typical_program(lines));
    int runs = lines <= 100 ? 41 : lines <= 3000 ? 11 : lines <= 10000 ? 5 : lines <= 30000 ? 3 : 1;
    // rcxc refuses a program too big for the brick after every pass has
    // run (program memory, or a branch too far): that is still the whole
    // compile. Any other refusal would time nothing: the row says so.
    std::string command = "'" + rcxc.string() + "' compile -w '" + file.string() + "' -o /dev/null";
    fs::path errors = dir / "errors.txt";
    int status = std::system((command + " >/dev/null 2>'" + errors.string() + "'").c_str());
    std::ifstream error_text(errors);
    std::string first_error;
    std::getline(error_text, first_error);
    if (status != 0 && first_error.find("program memory") == std::string::npos &&
        first_error.find("too far") == std::string::npos) {
      std::cout << fmt::format("{:>8} rcxc refuses it: {}\n", real_lines, first_error);
      continue;
    }
    // nqc looks for quoted includes in its -I folders, not beside the file.
    auto [ours, theirs] =
        median_cpu(command, "nqc -Trcx -I'" + dir.string() + "/' -O/dev/null '" + file.string() + "'", runs);
    if (!ours) break;
    std::cout << fmt::format("{:>8} {:>5} {:>12.1f} {:>12} {:>7} {:>14.1f}\n", real_lines, runs, *ours * 1000,
                             theirs ? fmt::format("{:.1f}", *theirs * 1000) : "fails",
                             theirs ? fmt::format("{:.2f}", *ours / *theirs) : "-",
                             *ours * 1e6 / static_cast<double>(real_lines));
  }
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

void BM_ManySubroutines(benchmark::State& state) {
  compile(state, many_subroutines(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_ManySubroutines)->Arg(100)->Arg(400)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  print_against_nqc(std::filesystem::absolute(argv[0]).parent_path().parent_path() / "rcxc");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
