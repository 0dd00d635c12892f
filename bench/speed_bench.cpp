// Speed on the brick against nqc, in one run, the figures README quotes.
//
// For every corpus program both compilers accept, both images run under
// `rcxc compare`'s built-in scenarios (verify/scenarios.h) at the brick's
// 2 ms per instruction for 20 s each, and the table gives per program:
//  * instructions executed (all scenarios together). A program that never
//    waits keeps the brick busy whatever its code ("busy": at least 95% of
//    the instructions 20 s can hold, on both sides); its count says nothing
//    of its code, so the instruction totals are over the other programs,
//    and a busy program's speed shows in its latency. A program that polls
//    an input between waits runs as many polls as fit in the time, so the
//    count of programs that end by themselves (their whole work) is given
//    apart;
//  * reaction latency: for every event both runs show (matched as
//    `rcxc compare` matches them), the time from the input before it (or
//    the program's start) to the event, summed; "later" when rcxc's sum is
//    larger, with the worst single lateness;
//  * code bytes at the default level (-O2) and at -Os.
// Then code size over generated programs (tests/support/random_programs.h,
// never used to tune the optimisations), and the compile time of the
// corpus: `rcxc compile` and `nqc` as processes, CPU time of each.
//
// The corpus is found through RCXC_CORPUS_DIR, or next to the source tree
// (../shared/corpus); nqc on PATH. Without either it says so and stops.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <regex>

#include <fmt/format.h>

#include "backend/compile.h"
#include "bench/corpus.h"
#include "tests/support/random_programs.h"
#include "verify/compare.h"
#include "verify/external_nqc.h"
#include "verify/scenarios.h"

namespace {

namespace fs = std::filesystem;

constexpr rcx::Micros kBrickInstructionUs = rcx::kDefaultInstructionCostUs;
constexpr rcx::Micros kRunUs = 20'000 * rcx::kMicrosPerMs;

using rcxc::bench::corpus_dir;
using rcxc::bench::corpus_files;

std::optional<rcxc::backend::Output> ours(const fs::path& file, rcxc::ir::OptLevel level) {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  rcxc::ir::Log log;
  return rcxc::backend::compile_file(file.string(), {}, level, sm, diags, log);
}

std::optional<int> nqc_bytes(const fs::path& file) {
  auto listing = rcxc::bench::nqc_listing(file);
  return listing ? rcxc::bench::nqc_bytes(*listing) : std::nullopt;
}

struct Speed {
  std::int64_t ours_instructions = 0, theirs_instructions = 0;
  bool busy = true;   // busy in every scenario, on both sides
  bool ended = true;  // ended by itself in every scenario, on both sides
  double ours_latency_ms = 0, theirs_latency_ms = 0;
  double worst_later_ms = 0;
  int events = 0;
  bool behaves_alike = true;
};

// The input time at or before `t` (0: the program's start).
rcx::Micros cause_of(const rcx::NamedScenario& s, rcx::Micros t) {
  rcx::Micros cause = 0;
  for (const auto& in : s.inputs)
    if (in.at_us <= t) cause = std::max(cause, in.at_us);
  return cause;
}

Speed measure_speed(const rcx::Image& mine, const rcx::Image& theirs) {
  Speed r;
  const std::int64_t capacity = kRunUs / kBrickInstructionUs;
  // At 2 ms per instruction the two codes drift apart by their instruction
  // counts; the events are paired in order, whatever the time between them.
  rcx::TimeTolerance pairing{kRunUs, 0, 5 * kBrickInstructionUs};
  for (const auto& s : rcx::builtin_scenarios()) {
    auto a = rcx::run_scenario(mine, s, kBrickInstructionUs, 1, kRunUs);
    auto b = rcx::run_scenario(theirs, s, kBrickInstructionUs, 1, kRunUs);
    r.ours_instructions += a.instructions_executed();
    r.theirs_instructions += b.instructions_executed();
    r.ended = r.ended && a.stop().kind == rcx::StopKind::Ended && b.stop().kind == rcx::StopKind::Ended;
    r.busy = r.busy && a.instructions_executed() * 100 >= capacity * 95 &&
             b.instructions_executed() * 100 >= capacity * 95;
    auto cmp = rcx::compare_runs({&a, &mine, "rcxc"}, {&b, &theirs, "nqc"}, pairing);
    r.behaves_alike = r.behaves_alike && cmp.same;
    for (const auto& m : cmp.matched) {
      rcx::Micros cause = cause_of(s, std::min(m.a_us, m.b_us));
      r.ours_latency_ms += static_cast<double>(m.a_us - cause) / rcx::kMicrosPerMs;
      r.theirs_latency_ms += static_cast<double>(m.b_us - cause) / rcx::kMicrosPerMs;
      r.worst_later_ms = std::max(r.worst_later_ms, static_cast<double>(m.a_us - m.b_us) / rcx::kMicrosPerMs);
      ++r.events;
    }
  }
  return r;
}

double ratio(double a, double b) { return b > 0 ? a / b : 1.0; }

struct Totals {
  std::int64_t ours_instructions = 0, theirs_instructions = 0;
  int more_instructions = 0, busy = 0;
  std::int64_t ours_ended = 0, theirs_ended = 0;  // programs that end by themselves
  int ended = 0;
  double ours_latency = 0, theirs_latency = 0;
  int later = 0, unlike = 0, events = 0;
  long o2_bytes = 0, os_bytes = 0, nqc_bytes = 0;
  int o2_larger = 0, os_larger = 0, programs = 0;
};

void print_corpus(Totals& t) {
  std::cout << "Corpus programs under the built-in scenarios, 2 ms per instruction, 20 s each\n";
  std::cout << fmt::format("{:<26} {:>9} {:>9} {:>6} {:>9} {:>9} {:>6} {:>7} {:>5} {:>5} {:>5}\n", "program",
                           "instr", "nqc", "ratio", "latency", "nqc", "ratio", "worst", "-O2", "-Os", "nqc");
  for (const auto& f : corpus_files()) {
    auto theirs = rcx::semtest::compile_with_nqc("nqc", f.string());
    auto bytes = nqc_bytes(f);
    auto o2 = ours(f, rcxc::ir::OptLevel::O2);
    auto os = ours(f, rcxc::ir::OptLevel::Os);
    if (!theirs.image || !bytes || !o2 || !os) continue;
    Speed s = measure_speed(o2->image, *theirs.image);
    ++t.programs;
    if (s.busy) {
      ++t.busy;
    } else {
      t.ours_instructions += s.ours_instructions;
      t.theirs_instructions += s.theirs_instructions;
      t.more_instructions += s.ours_instructions > s.theirs_instructions;
    }
    if (s.ended) {
      t.ours_ended += s.ours_instructions;
      t.theirs_ended += s.theirs_instructions;
      ++t.ended;
    }
    t.ours_latency += s.ours_latency_ms;
    t.theirs_latency += s.theirs_latency_ms;
    t.later += s.ours_latency_ms > s.theirs_latency_ms;
    t.events += s.events;
    t.unlike += !s.behaves_alike;
    t.o2_bytes += o2->code_bytes;
    t.os_bytes += os->code_bytes;
    t.nqc_bytes += *bytes;
    t.o2_larger += o2->code_bytes > *bytes;
    t.os_larger += os->code_bytes > *bytes;
    std::cout << fmt::format("{:<26} {:>9} {:>9} {:>6.2f} {:>9.0f} {:>9.0f} {:>6.3f} {:>7.0f} {:>5} {:>5} {:>5}{}{}\n",
                             f.filename().string(), s.ours_instructions, s.theirs_instructions,
                             ratio(static_cast<double>(s.ours_instructions), static_cast<double>(s.theirs_instructions)),
                             s.ours_latency_ms, s.theirs_latency_ms, ratio(s.ours_latency_ms, s.theirs_latency_ms),
                             s.worst_later_ms, o2->code_bytes, os->code_bytes, *bytes,
                             s.busy ? "  busy" : s.ended ? "  ends" : "",
                             s.behaves_alike ? "" : "  (events differ at 2 ms)");
  }
}

struct SizeTotals {
  long o2 = 0, os = 0, nqc = 0;
  int o2_larger = 0, os_larger = 0, programs = 0;
  std::vector<std::string> larger;  // "kind seed: -O2 / -Os vs nqc bytes"
};

// Generated programs of several kinds, the same seeds every run.
SizeTotals generated_sizes() {
  fs::path dir = fs::temp_directory_path() / fmt::format("rcxc-speed-{}", getpid());
  fs::create_directories(dir);
  fs::path file = dir / "generated.nqc";
  SizeTotals t;
  auto add = [&](const std::string& text, const std::string& name) {
    std::ofstream(file) << text;
    auto b = nqc_bytes(file);
    auto o2 = ours(file, rcxc::ir::OptLevel::O2);
    auto os = ours(file, rcxc::ir::OptLevel::Os);
    if (!b || !o2 || !os) return;
    t.o2 += o2->code_bytes;
    t.os += os->code_bytes;
    t.nqc += *b;
    t.o2_larger += o2->code_bytes > *b;
    t.os_larger += os->code_bytes > *b;
    if (o2->code_bytes > *b || os->code_bytes > *b)
      t.larger.push_back(fmt::format("{}: {} / {} vs {} bytes", name, o2->code_bytes, os->code_bytes, *b));
    ++t.programs;
  };
  using namespace rcxc::test;
  for (unsigned seed = 1; seed <= 200; ++seed)
    add(ExpressionGenerator(seed, true).program(), fmt::format("expressions {}", seed));
  for (unsigned seed = 1; seed <= 100; ++seed) {
    add(Generator(seed).program(), fmt::format("motors {}", seed));
    add(TwoTaskGenerator(seed).program(), fmt::format("two tasks {}", seed));
    add(CallNeighbourGenerator(seed).program(), fmt::format("calls {}", seed));
  }
  fs::remove_all(dir);
  return t;
}

// CPU seconds the children spent so far.
double children_cpu() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

// CPU time of compiling every corpus program `rounds` times with `command`
// (FILE replaced by the program), as processes.
double compile_cpu(const std::string& command, const std::vector<fs::path>& files, int rounds) {
  double before = children_cpu();
  for (int r = 0; r < rounds; ++r)
    for (const auto& f : files) {
      std::string cmd = std::regex_replace(command, std::regex("FILE"), "'" + f.string() + "'");
      if (std::system((cmd + " >/dev/null 2>&1").c_str()) == -1) return 0;
    }
  return children_cpu() - before;
}

fs::path rcxc_binary(const char* argv0) { return fs::absolute(argv0).parent_path().parent_path() / "rcxc"; }

}  // namespace

int main(int, char** argv) {
  if (corpus_files().empty() || !nqc_bytes(corpus_files().front())) {
    std::cout << "speed_bench: needs the corpus (" << corpus_dir().string() << ") and nqc on PATH\n";
    return 0;
  }
  Totals t;
  print_corpus(t);
  SizeTotals g = generated_sizes();
  const int rounds = 5;
  double rcxc_cpu = compile_cpu(rcxc_binary(argv[0]).string() + " compile FILE -o /dev/null", corpus_files(), rounds);
  double nqc_cpu = compile_cpu("nqc -Trcx -O/dev/null FILE", corpus_files(), rounds);
  int compiles = rounds * static_cast<int>(corpus_files().size());

  std::cout << "\nAgainst nqc (rcxc / nqc; lower is better)\n";
  std::cout << fmt::format("  executed instructions   {:.3f}  ({} vs {} over {} programs that wait; {} more than "
                           "nqc's; {} busy programs left out)\n",
                           ratio(static_cast<double>(t.ours_instructions), static_cast<double>(t.theirs_instructions)),
                           t.ours_instructions, t.theirs_instructions, t.programs - t.busy, t.more_instructions,
                           t.busy);
  std::cout << fmt::format("    of which programs that end  {:.3f}  ({} vs {} over {} programs: their whole work)\n",
                           ratio(static_cast<double>(t.ours_ended), static_cast<double>(t.theirs_ended)),
                           t.ours_ended, t.theirs_ended, t.ended);
  double per_event = t.events > 0 ? 1.0 / t.events : 0;
  std::cout << fmt::format("  reaction latency        {:.3f}  (from input to event, {:.1f} vs {:.1f} ms on average over "
                           "{} matched events; {} programs react later than nqc's; {} differ at 2 ms)\n",
                           ratio(t.ours_latency, t.theirs_latency), t.ours_latency * per_event,
                           t.theirs_latency * per_event, t.events, t.later, t.unlike);
  std::cout << fmt::format("  code size, corpus       {:.3f} at -O2, {:.3f} at -Os  ({} / {} vs {} bytes; larger: {} "
                           "at -O2, {} at -Os)\n",
                           ratio(static_cast<double>(t.o2_bytes), static_cast<double>(t.nqc_bytes)),
                           ratio(static_cast<double>(t.os_bytes), static_cast<double>(t.nqc_bytes)), t.o2_bytes,
                           t.os_bytes, t.nqc_bytes, t.o2_larger, t.os_larger);
  std::cout << fmt::format("  code size, generated    {:.3f} at -O2, {:.3f} at -Os  ({} / {} vs {} bytes, {} "
                           "programs; larger: {} at -O2, {} at -Os)\n",
                           ratio(static_cast<double>(g.o2), static_cast<double>(g.nqc)),
                           ratio(static_cast<double>(g.os), static_cast<double>(g.nqc)), g.o2, g.os, g.nqc,
                           g.programs, g.o2_larger, g.os_larger);
  for (const auto& l : g.larger) std::cout << "    larger than nqc's: " << l << "\n";
  std::cout << fmt::format("  compile time (CPU)      {:.3f}  ({:.1f} vs {:.1f} ms per corpus program, as processes)\n",
                           ratio(rcxc_cpu, nqc_cpu), rcxc_cpu * 1000 / compiles, nqc_cpu * 1000 / compiles);
  return 0;
}
