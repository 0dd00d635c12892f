// Code size at the default level (-O2, the fastest code, never larger
// than nqc's) and at -Os (the smallest): for every corpus program, rcxc's
// code bytes and variable slots against `nqc -Trcx` (when nqc is
// installed), as a table with the totals; then the totals over 400 random
// programs (tests/support/random_programs.h) at both levels, naming the
// seeds of any program larger than nqc's; the totals over programs from
// elsewhere when RCXC_OUTSIDE_DIR names a folder of them; plus the compile time of each
// corpus program at -Os as the benchmark proper. speed_bench gives the
// sizes of the other generated kinds (motor sequences, two tasks, calls).
//
// The corpus is found through the RCXC_CORPUS_DIR environment variable, or
// next to the source tree (../shared/corpus).
#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string_view>

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "backend/compile.h"
#include "bench/corpus.h"
#include "runtime/vm.h"
#include "tests/support/random_programs.h"
#include "verify/external_nqc.h"

namespace {

namespace fs = std::filesystem;

using rcxc::bench::corpus_files;

struct Size {
  int bytes = 0;
  int slots = 0;
};

std::optional<Size> ours(const fs::path& file, rcxc::ir::OptLevel level = rcxc::ir::OptLevel::Os) {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  rcxc::ir::Log log;
  auto out = rcxc::backend::compile_file(file.string(), {}, level, sm, diags, log);
  if (!out) return std::nullopt;
  return Size{out->code_bytes, out->slots_used};
}

// nqc's listing ends with "Total size: N bytes" and names variables as
// "*** Var N = name".
std::optional<Size> theirs(const fs::path& file) {
  auto text = rcxc::bench::nqc_listing(file);
  if (!text) return std::nullopt;
  auto bytes = rcxc::bench::nqc_bytes(*text);
  if (!bytes) return std::nullopt;
  Size s{*bytes, 0};
  std::set<int> vars;
  std::regex var("\\*\\*\\* Var ([0-9]+) =");
  for (auto it = std::sregex_iterator(text->begin(), text->end(), var); it != std::sregex_iterator(); ++it)
    vars.insert(std::stoi((*it)[1]));
  s.slots = static_cast<int>(vars.size());
  return s;
}

// Whether nqc's code for `file` faults within 20 s of brick time with no
// input: nqc's long-branch bug writes a forward test more than 127 bytes
// away as a short one whose offset wraps (docs/compiler.md), which is
// shorter than the long test correct code needs. Being larger than such
// code is no loss: it is named apart.
bool nqc_code_faults(const fs::path& file) {
  auto theirs = rcx::semtest::compile_with_nqc("nqc", file.string());
  if (!theirs.image) return false;
  rcx::Machine m(rcx::Config{});
  if (m.load(0, *theirs.image)) return false;
  m.start_program();
  return m.run_until(20'000 * rcx::kMicrosPerMs).kind == rcx::StopKind::Fault;
}

// The programs larger than nqc's code at each level, by seed or by file
// name; those whose nqc code faults named apart (nqc_code_faults).
template <class Name>
struct Larger {
  std::vector<Name> o2, os, nqc_wrong;

  void add(const Size& o2_size, const Size& os_size, const Size& theirs, const fs::path& file, const Name& name) {
    if (o2_size.bytes <= theirs.bytes && os_size.bytes <= theirs.bytes) return;
    if (nqc_code_faults(file)) return nqc_wrong.push_back(name);
    if (o2_size.bytes > theirs.bytes) o2.push_back(name);
    if (os_size.bytes > theirs.bytes) os.push_back(name);
  }

  // `what` before the names: "seeds " or nothing.
  void print(std::string_view what) const {
    if (!o2.empty()) std::cout << fmt::format("larger at -O2: {}{}\n", what, fmt::join(o2, ", "));
    if (!os.empty()) std::cout << fmt::format("larger at -Os: {}{}\n", what, fmt::join(os, ", "));
    if (!nqc_wrong.empty())
      std::cout << fmt::format("larger than nqc's code, which faults (its long-branch bug), not counted as larger: {}{}\n",
                               what, fmt::join(nqc_wrong, ", "));
  }
};

void print_table() {
  int o2_total = 0, os_total = 0, theirs_total = 0, o2_larger = 0, os_larger = 0;
  std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6} {:>6} {:>6} {:>10} {:>10}\n", "program", "-O2", "-Os", "nqc",
                           "-O2/nqc", "-Os/nqc", "rcxc slots", "nqc slots");
  for (const auto& f : corpus_files()) {
    auto o2 = ours(f, rcxc::ir::OptLevel::O2);
    auto a = ours(f);
    auto b = theirs(f);
    std::string name = f.filename().string();
    if (!a || !o2) {
      std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6}\n", name, "error", "error", b ? std::to_string(b->bytes) : "error");
      continue;
    }
    if (!b) {
      std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6} {:>7} {:>7} {:>10}\n", name, o2->bytes, a->bytes, "-", "-", "-",
                               a->slots);
      continue;
    }
    o2_total += o2->bytes;
    os_total += a->bytes;
    theirs_total += b->bytes;
    o2_larger += o2->bytes > b->bytes ? 1 : 0;
    os_larger += a->bytes > b->bytes ? 1 : 0;
    std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6} {:>7.2f} {:>7.2f} {:>10} {:>10}\n", name, o2->bytes, a->bytes,
                             b->bytes, static_cast<double>(o2->bytes) / b->bytes,
                             static_cast<double>(a->bytes) / b->bytes, a->slots, b->slots);
  }
  if (theirs_total > 0)
    std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6} {:>7.3f} {:>7.3f}   (larger than nqc's: {} at -O2, {} at -Os)\n",
                             "total", o2_total, os_total, theirs_total, static_cast<double>(o2_total) / theirs_total,
                             static_cast<double>(os_total) / theirs_total, o2_larger, os_larger);
  else
    std::cout << "(nqc not installed or corpus absent: no comparison)\n";
}

// Random programs of arithmetic, tests and loops: a wider sample than the
// corpus, the same seeds every run (README's figures), or 400 others with
// RCXC_SEED_OFFSET=N (seeds N+1 to N+400, as the random-program tests take
// it): programs no optimisation was ever looked at on.
void print_random_totals() {
  fs::path dir = fs::temp_directory_path() / fmt::format("rcxc-size-{}", getpid());
  fs::create_directories(dir);
  fs::path file = dir / "random.nqc";
  long o2_total = 0, os_total = 0, theirs_total = 0;
  int compared = 0;
  Larger<unsigned> larger;
  const unsigned first = rcxc::test::seed_offset() + 1;
  for (unsigned seed = first; seed < first + 400; ++seed) {
    std::ofstream(file) << rcxc::test::ExpressionGenerator(seed, true).program();
    auto o2 = ours(file, rcxc::ir::OptLevel::O2);
    auto a = ours(file);
    auto b = theirs(file);
    if (!o2 || !a || !b) continue;
    o2_total += o2->bytes;
    os_total += a->bytes;
    theirs_total += b->bytes;
    larger.add(*o2, *a, *b, file, seed);
    ++compared;
  }
  fs::remove_all(dir);
  if (theirs_total > 0)
    std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6} {:>7.3f} {:>7.3f}   ({} random programs, seeds {} to {}; larger "
                             "than nqc's: {} at -O2, {} at -Os)\n",
                             "random programs", o2_total, os_total, theirs_total,
                             static_cast<double>(o2_total) / theirs_total, static_cast<double>(os_total) / theirs_total,
                             compared, first, first + 399, larger.o2.size(), larger.os.size());
  larger.print("seeds ");
}

// Programs from elsewhere (RCXC_OUTSIDE_DIR): the figure for programs the
// project has never seen. Those nqc refuses are left out, and named.
void print_outside_totals() {
  const auto files = rcxc::bench::outside_files();
  if (files.empty()) return;
  long o2_total = 0, os_total = 0, theirs_total = 0;
  Larger<std::string> larger;
  std::vector<std::string> left_out;
  for (const auto& f : files) {
    auto o2 = ours(f, rcxc::ir::OptLevel::O2);
    auto a = ours(f);
    auto b = theirs(f);
    if (!o2 || !a || !b) {
      left_out.push_back(f.filename().string());
      continue;
    }
    o2_total += o2->bytes;
    os_total += a->bytes;
    theirs_total += b->bytes;
    larger.add(*o2, *a, *b, f, f.filename().string());
  }
  if (theirs_total > 0)
    std::cout << fmt::format("{:<24} {:>6} {:>6} {:>6} {:>7.3f} {:>7.3f}   ({} programs from elsewhere; larger than "
                             "nqc's: {} at -O2, {} at -Os)\n",
                             "from elsewhere", o2_total, os_total, theirs_total,
                             static_cast<double>(o2_total) / theirs_total, static_cast<double>(os_total) / theirs_total,
                             files.size() - left_out.size(), larger.o2.size(), larger.os.size());
  larger.print("");
  if (!left_out.empty())
    std::cout << fmt::format("left out (a compiler refuses them): {}\n", fmt::join(left_out, ", "));
}

void BM_Compile(benchmark::State& state, const fs::path& file) {
  std::optional<Size> size;
  for (auto _ : state) {
    size = ours(file);
    benchmark::DoNotOptimize(size);
  }
  if (size) {
    state.counters["code_bytes"] = size->bytes;
    state.counters["slots"] = size->slots;
  }
}

}  // namespace

int main(int argc, char** argv) {
  print_table();
  print_random_totals();
  print_outside_totals();
  for (const auto& f : corpus_files())
    benchmark::RegisterBenchmark(("compile/" + f.filename().string()).c_str(), BM_Compile, f);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
