// Code size at -Os (the smallest code): for every corpus program, rcxc's
// code bytes and variable slots against `nqc -Trcx` (when nqc is
// installed), as a table with the totals;
// then the totals over 400 random programs (tests/support/random_programs.h);
// plus the compile time of each corpus program as the benchmark proper.
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

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "backend/compile.h"
#include "bench/corpus.h"
#include "tests/support/random_programs.h"

namespace {

namespace fs = std::filesystem;

using rcxc::bench::corpus_files;

struct Size {
  int bytes = 0;
  int slots = 0;
};

std::optional<Size> ours(const fs::path& file) {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  rcxc::ir::Log log;
  auto out = rcxc::backend::compile_file(file.string(), {}, rcxc::ir::OptLevel::Os, sm, diags, log);
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

void print_table() {
  int ours_total = 0, theirs_total = 0, larger = 0;
  std::cout << fmt::format("{:<24} {:>9} {:>9} {:>6} {:>10} {:>10}\n", "program", "rcxc", "nqc", "ratio", "rcxc slots",
                           "nqc slots");
  for (const auto& f : corpus_files()) {
    auto a = ours(f);
    auto b = theirs(f);
    std::string name = f.filename().string();
    if (!a) {
      std::cout << fmt::format("{:<24} {:>9} {:>9}\n", name, "error", b ? std::to_string(b->bytes) : "error");
      continue;
    }
    if (!b) {
      std::cout << fmt::format("{:<24} {:>9} {:>9} {:>6} {:>10}\n", name, a->bytes, "-", "-", a->slots);
      continue;
    }
    ours_total += a->bytes;
    theirs_total += b->bytes;
    larger += a->bytes > b->bytes ? 1 : 0;
    std::cout << fmt::format("{:<24} {:>9} {:>9} {:>6.2f} {:>10} {:>10}\n", name, a->bytes, b->bytes,
                             static_cast<double>(a->bytes) / b->bytes, a->slots, b->slots);
  }
  if (theirs_total > 0)
    std::cout << fmt::format("{:<24} {:>9} {:>9} {:>6.3f}   ({} programs larger than nqc's)\n", "total", ours_total,
                             theirs_total, static_cast<double>(ours_total) / theirs_total, larger);
  else
    std::cout << "(nqc not installed or corpus absent: no comparison)\n";
}

// Random programs of arithmetic, tests and loops: a wider sample than the
// corpus, the same seeds every run.
void print_random_totals() {
  fs::path dir = fs::temp_directory_path() / fmt::format("rcxc-size-{}", getpid());
  fs::create_directories(dir);
  fs::path file = dir / "random.nqc";
  long ours_total = 0, theirs_total = 0;
  int compared = 0;
  std::vector<unsigned> larger_seeds;
  for (unsigned seed = 1; seed <= 400; ++seed) {
    std::ofstream(file) << rcxc::test::ExpressionGenerator(seed, true).program();
    auto a = ours(file);
    auto b = theirs(file);
    if (!a || !b) continue;
    ours_total += a->bytes;
    theirs_total += b->bytes;
    if (a->bytes > b->bytes) larger_seeds.push_back(seed);
    ++compared;
  }
  fs::remove_all(dir);
  if (theirs_total > 0)
    std::cout << fmt::format("{:<24} {:>9} {:>9} {:>6.3f}   ({} random programs, {} larger than nqc's)\n",
                             "random programs", ours_total, theirs_total,
                             static_cast<double>(ours_total) / theirs_total, compared, larger_seeds.size());
  if (!larger_seeds.empty()) std::cout << fmt::format("larger: seeds {}\n", fmt::join(larger_seeds, ", "));
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
  for (const auto& f : corpus_files())
    benchmark::RegisterBenchmark(("compile/" + f.filename().string()).c_str(), BM_Compile, f);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
