// Speed on the brick against nqc, in one run, the figures README quotes.
//
// For every corpus program both compilers accept, both images run under
// `rcxc compare`'s built-in scenarios (verify/scenarios.h) at the brick's
// 2 ms per instruction for 20 s each. A fixed scenario time cannot show
// faster code through total instructions: a program that polls without
// waiting executes 500 instructions a second whatever its code. So the
// measures the goals are judged on are what a user feels (docs/compiler.md,
// "Speed on the brick"), per program:
//  * instructions per loop pass: the run stepped one instruction at a time,
//    a pass is a task going back to an instruction of its code at or before
//    the one it ran (a loop's back edge, a poll that branches to itself);
//    instructions executed / passes. Fewer is a loop that looks at its
//    inputs more often. Programs with no pass (they end) are left out;
//  * reaction, in instructions: for each input change, the output change
//    it caused (where the run parts from a run of the same code without
//    that change, before the next change; verify/compare.h parting_time),
//    and the instructions the brick executed (all tasks) from the change
//    to it, over input_phases() runs of each scenario, its changes moved
//    in all but the first (jittered_inputs: where a change falls in a pass
//    or a wait decides its reaction). A program reacts later only beyond
//    the noise of those timings (reacts_later). Idle time in waits, the
//    same for both codes, is no instruction; another task's polls during a
//    wait are. Printed too: the same count to the first event after each
//    change, caused by it or not (an earlier measure, which counted a
//    task's timed moves as reactions);
//  * work of programs that end by themselves: their instructions, less
//    polls in place (a test that branches to itself is waiting for an
//    input or a timer, not working);
//  * work of generated programs that end without polling, the same way,
//    with no input: programs never used to tune the optimisations.
// Printed too, for comparison with earlier figures: the total instructions
// over the fixed time (busy programs, which fill the time whatever their
// code, left out), and reaction latency in brick time at 2 ms per
// instruction, waits included, summed over every matched event; and code
// bytes at the default level (-O2) and at -Os.
// Then code size over generated programs (tests/support/random_programs.h,
// never used to tune the optimisations), and the compile time of the
// corpus: `rcxc compile` and `nqc` as processes, CPU time of each.
// RCXC_SPEED_TRACE=1 prints every reaction measured to stderr;
// RCXC_BENCH_PROGRAMS=DIR keeps the generated control loops there.
//
// The corpus is found through RCXC_CORPUS_DIR, or next to the source tree
// (../shared/corpus); nqc on PATH. Without either it says so and stops.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <random>
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
constexpr std::int64_t kShortReaction = 10;  // instructions
// Where an input change falls in a loop's pass, or in another task's wait,
// decides its reaction, so reactions are measured over this many runs of
// each scenario: as written, then with its changes moved by pseudo-random
// delays (jittered_inputs). Inputs shifted together by one instruction a
// phase (the earlier design, 8 phases) sampled 16 ms of a wait's cycle and
// followed a scenario's round intervals: a loop whose pass is 200 ms met
// every change in the same place, and the total swung between 0.88 and
// 1.03 with the phases chosen. From 32 runs to 128 it stays within a few
// hundredths (docs/compiler.md). RCXC_SPEED_PHASES=N runs N instead.
int input_phases() {
  const char* env = std::getenv("RCXC_SPEED_PHASES");
  int n = env ? std::atoi(env) : 64;
  return std::max(1, n);
}

using rcxc::bench::corpus_dir;
using rcxc::bench::corpus_files;
using rcxc::bench::children_cpu_seconds;

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

// One run stepped an instruction at a time, for the per-pass and
// per-reaction measures.
struct Profile {
  std::vector<rcx::Micros> step_end_us;  // when each executed instruction ended, in order
  std::int64_t passes = 0;
  std::int64_t polls_in_place = 0;  // tests that branched to themselves: waiting, not work

  // Instructions that ended at or before `t`.
  std::int64_t instructions_by(rcx::Micros t) const {
    return std::upper_bound(step_end_us.begin(), step_end_us.end(), t) - step_end_us.begin();
  }
};

Profile profile(const rcx::Image& image, const rcx::NamedScenario& s) {
  rcx::Config config;
  config.seed = 1;
  config.instruction_cost_us = kBrickInstructionUs;
  rcx::Machine m(config);
  if (auto error = m.load(0, image)) throw std::runtime_error(*error);
  for (const auto& in : s.inputs) m.schedule(in);
  m.start_program();
  Profile p;
  struct Where {
    bool active;
    int sub, pc;
  };
  std::array<Where, rcx::kMaxTasks> before{};
  while (m.now_us() < kRunUs) {
    for (int i = 0; i < rcx::kMaxTasks; ++i) before[static_cast<std::size_t>(i)] = {m.task(i).active, m.task(i).sub, m.task(i).pc};
    std::int64_t count = m.instructions_executed();
    std::size_t events = m.state().events.size();
    const auto& stop = m.run_until(std::min(m.now_us() + kBrickInstructionUs, kRunUs));
    if (m.instructions_executed() > count) {
      p.step_end_us.push_back(m.now_us());
      // The task that ran moved forward, or back (a pass), or stayed on a
      // test that branches to itself (a pass); a task that the instruction
      // started afresh begins at 0 and is no pass.
      bool moved = false, back = false;
      for (int i = 0; i < rcx::kMaxTasks; ++i) {
        const auto& w = before[static_cast<std::size_t>(i)];
        const auto& t = m.task(i);
        bool restarted = std::any_of(m.state().events.begin() + static_cast<std::ptrdiff_t>(events),
                                     m.state().events.end(), [&](const rcx::Event& e) {
                                       return e.kind == rcx::EventKind::TaskStart && e.index == i;
                                     });
        if (!w.active || restarted || (t.active && t.sub == w.sub && t.pc == w.pc)) continue;
        moved = true;
        back = back || (t.active && t.sub == w.sub && t.pc < w.pc);
      }
      p.passes += back || !moved;
      p.polls_in_place += !moved;
    }
    if (stop.kind != rcx::StopKind::Running) break;
  }
  return p;
}

struct Speed {
  std::int64_t ours_instructions = 0, theirs_instructions = 0;
  std::int64_t ours_passes = 0, theirs_passes = 0;
  std::int64_t ours_pass_instructions = 0, theirs_pass_instructions = 0;  // of the profiled runs
  std::int64_t ours_reaction = 0, theirs_reaction = 0;                    // instructions, input to the event it caused
  int reactions = 0;
  double reaction_difference_squares = 0;  // sum over reactions of (ours - theirs)^2
  std::int64_t ours_first = 0, theirs_first = 0;  // instructions, input to the first event after it
  int firsts = 0;
  // The reactions that took at most kShortReaction instructions with both
  // codes: the code's own path from the test to the output, where a longer
  // one has mostly waited (another task's polls during a Wait count).
  std::int64_t ours_short = 0, theirs_short = 0;
  int shorts = 0;
  std::int64_t ours_work = 0, theirs_work = 0;  // instructions less polls in place
  bool busy = true;   // busy in every scenario, on both sides
  bool ended = true;  // ended by itself in every scenario, on both sides
  double ours_latency_ms = 0, theirs_latency_ms = 0;
  double worst_later_ms = 0;
  int events = 0;
  bool behaves_alike = true;
};

// Whether rcxc's code reacted later than nqc's by more than where the
// inputs happened to fall explains: the mean of the paired differences
// (rcxc's count less nqc's, one per reaction) above twice its standard
// error. A reaction through a wait differs by hundreds of instructions
// either way with the input's timing (another task polls through the
// wait), one on the code's own path by a few; a total higher by less than
// that spread is the draw of input timings, not the code.
bool reacts_later(const Speed& s) {
  if (s.ours_reaction <= s.theirs_reaction) return false;
  if (s.reactions < 2) return true;
  double n = s.reactions;
  double mean = static_cast<double>(s.ours_reaction - s.theirs_reaction) / n;
  double variance = std::max(0.0, (s.reaction_difference_squares / n - mean * mean) * n / (n - 1));
  return mean > 2 * std::sqrt(variance / n);
}

// The programs whose reactions took more instructions than nqc's code's:
// beyond the noise of the timings (named), or within it (counted).
struct ReactionVerdicts {
  int slower = 0, within_noise = 0;
  std::vector<std::string> names;

  void add(const Speed& s, std::string_view program, std::string_view remark = "") {
    if (reacts_later(s)) {
      ++slower;
      names.push_back(fmt::format("{}: {} vs {} instructions{}", program, s.ours_reaction, s.theirs_reaction, remark));
    } else {
      within_noise += s.ours_reaction > s.theirs_reaction;
    }
  }
};

// The input time at or before `t` (0: the program's start).
rcx::Micros cause_of(const rcx::NamedScenario& s, rcx::Micros t) {
  rcx::Micros cause = 0;
  for (const auto& in : s.inputs)
    if (in.at_us <= t) cause = std::max(cause, in.at_us);
  return cause;
}

// When the change of inputs at `from` first made `image`'s run `with` (the
// whole scenario) show something it would not have shown without it: the
// run again with only the inputs before `from`, up to `until` (the next
// change), and where the two part. nullopt: nothing before `until`, as a
// change the program ignores or only remembers.
std::optional<rcx::Micros> caused_at(const rcx::Image& image, const rcx::Machine& with, const rcx::NamedScenario& s,
                                     rcx::Micros from, rcx::Micros until) {
  std::vector<rcx::TimedInput> before;
  for (const auto& in : s.inputs)
    if (in.at_us < from) before.push_back(in);
  rcx::Machine without = rcx::start_scenario(image, before, kBrickInstructionUs, 1);
  without.run(until);
  auto t = rcx::parting_time(with, without, from);
  if (!t || *t >= until) return std::nullopt;
  return t;
}

// RCXC_SPEED_TRACE set: each reaction measured, one line on stderr, for
// reading one program's figures (which change, when each code acted).
struct Trace {
  bool on = false;
  std::string program;
};

// The times the inputs change (inputs at one instant are one change).
std::vector<rcx::Micros> changes_of(const rcx::NamedScenario& s) {
  std::vector<rcx::Micros> changes;
  for (const auto& in : s.inputs) changes.push_back(in.at_us);
  std::sort(changes.begin(), changes.end());
  changes.erase(std::unique(changes.begin(), changes.end()), changes.end());
  return changes;
}

// `s` with its input changes moved later: all by one draw from [0, 5 s),
// so that where a change falls in a loop's pass or a wait is spread over
// many cycles of any loop (a range of a few cycles favours some places),
// and each by a draw of its own from [0, half the shortest gap between
// changes), so that a loop whose pass divides the scenario's round
// intervals (200 ms into 2 s) does not meet every change in the same
// place. Whole instructions; the changes keep their order, changes at the
// same time (the light scenario's three sensors) move together, and the
// inputs at 0 ms, the state the program starts in, stay. The same phase
// always draws the same delays.
rcx::NamedScenario jittered_inputs(const rcx::NamedScenario& s, int phase) {
  std::vector<rcx::Micros> changes = changes_of(s);
  rcx::Micros gap = kRunUs;
  for (std::size_t c = 1; c < changes.size(); ++c) gap = std::min(gap, changes[c] - changes[c - 1]);
  std::mt19937_64 draw(static_cast<std::uint64_t>(phase));
  auto slots = [&](rcx::Micros span) {
    return std::uniform_int_distribution<rcx::Micros>(0, std::max<rcx::Micros>(0, span / kBrickInstructionUs - 1))(draw) *
           kBrickInstructionUs;
  };
  rcx::Micros common = slots(5'000 * rcx::kMicrosPerMs);
  std::map<rcx::Micros, rcx::Micros> delay;
  for (rcx::Micros at : changes) delay[at] = at == 0 ? 0 : common + slots(gap / 2);
  rcx::NamedScenario out = s;
  for (auto& in : out.inputs) in.at_us += delay.at(in.at_us);
  return out;
}

// One code's run of a scenario, whole and stepped.
struct Ran {
  const rcx::Image& image;
  const rcx::Machine& run;
  Profile profile;
};

// For each input change of `s`, the output change it caused in each code
// (caused_at), both before the next change, and the instructions to it.
void add_caused_reactions(const Ran& ours, const Ran& theirs, const rcx::NamedScenario& s, int phase, Speed& r,
                          const Trace& trace) {
  std::vector<rcx::Micros> changes = changes_of(s);
  for (std::size_t c = 0; c < changes.size(); ++c) {
    rcx::Micros from = changes[c], until = c + 1 < changes.size() ? changes[c + 1] : kRunUs;
    auto ours_caused = caused_at(ours.image, ours.run, s, from, until);
    auto theirs_caused = caused_at(theirs.image, theirs.run, s, from, until);
    if (!ours_caused || !theirs_caused) continue;
    std::int64_t ours_count = ours.profile.instructions_by(*ours_caused) - ours.profile.instructions_by(from);
    std::int64_t theirs_count = theirs.profile.instructions_by(*theirs_caused) - theirs.profile.instructions_by(from);
    if (trace.on)
      std::cerr << fmt::format("{}, {}, phase {}: change at {} ms; rcxc acted at {} ms ({} instructions), "
                               "nqc at {} ms ({})\n",
                               trace.program, s.name, phase,
                               from / rcx::kMicrosPerMs, *ours_caused / rcx::kMicrosPerMs, ours_count,
                               *theirs_caused / rcx::kMicrosPerMs, theirs_count);
    r.ours_reaction += ours_count;
    r.theirs_reaction += theirs_count;
    r.reaction_difference_squares += static_cast<double>((ours_count - theirs_count) * (ours_count - theirs_count));
    if (ours_count <= kShortReaction && theirs_count <= kShortReaction) {
      r.ours_short += ours_count;
      r.theirs_short += theirs_count;
      ++r.shorts;
    }
    ++r.reactions;
  }
}

Speed measure_speed(const rcx::Image& mine, const rcx::Image& theirs, const Trace& trace) {
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
    Profile pa = profile(mine, s), pb = profile(theirs, s);
    r.ours_passes += pa.passes;
    r.theirs_passes += pb.passes;
    r.ours_work += static_cast<std::int64_t>(pa.step_end_us.size()) - pa.polls_in_place;
    r.theirs_work += static_cast<std::int64_t>(pb.step_end_us.size()) - pb.polls_in_place;
    r.ours_pass_instructions += static_cast<std::int64_t>(pa.step_end_us.size());
    r.theirs_pass_instructions += static_cast<std::int64_t>(pb.step_end_us.size());
    // Each input change and the first matched event after it, before the
    // next change.
    std::vector<rcx::Micros> changes = changes_of(s);
    for (std::size_t c = 0; c < changes.size(); ++c) {
      rcx::Micros from = changes[c], until = c + 1 < changes.size() ? changes[c + 1] : kRunUs;
      auto first = std::find_if(cmp.matched.begin(), cmp.matched.end(), [&](const rcx::MatchedEvent& m) {
        return m.a_us >= from && m.b_us >= from;
      });
      if (first != cmp.matched.end() && first->a_us < until && first->b_us < until) {
        r.ours_first += pa.instructions_by(first->a_us) - pa.instructions_by(from);
        r.theirs_first += pb.instructions_by(first->b_us) - pb.instructions_by(from);
        ++r.firsts;
      }
    }
    // The reactions, at each phase of the inputs against the instructions.
    add_caused_reactions({mine, a, pa}, {theirs, b, pb}, s, 0, r, trace);
    for (int phase = 1, phases = input_phases(); phase < phases; ++phase) {
      rcx::NamedScenario shifted = jittered_inputs(s, phase);
      auto a2 = rcx::run_scenario(mine, shifted, kBrickInstructionUs, 1, kRunUs);
      auto b2 = rcx::run_scenario(theirs, shifted, kBrickInstructionUs, 1, kRunUs);
      add_caused_reactions({mine, a2, profile(mine, shifted)}, {theirs, b2, profile(theirs, shifted)}, shifted, phase, r,
                           trace);
    }
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

double per_pass(std::int64_t instructions, std::int64_t passes) {
  return passes > 0 ? static_cast<double>(instructions) / static_cast<double>(passes) : 0;
}

// Per loop pass over a set of programs: the geometric mean of the programs'
// ratios (each program counts once, whatever its pass count), the programs
// slower per pass, and the one with the highest ratio.
struct PassRatios {
  double log_sum = 0;
  int looping = 0, slower = 0;
  std::string worst;
  double worst_ratio = 0;

  // One program's instructions per pass with each code (0: it never looped).
  void add(const Speed& s, const std::string& name) {
    double ours = per_pass(s.ours_pass_instructions, s.ours_passes);
    double theirs = per_pass(s.theirs_pass_instructions, s.theirs_passes);
    if (ours <= 0 || theirs <= 0) return;
    double r = ours / theirs;
    log_sum += std::log(r);
    ++looping;
    // Counted as slower only past rounding: a pass count that differs by
    // one at the end of the 20 s is no slower code.
    slower += r > 1.001;
    if (r > worst_ratio) {
      worst_ratio = r;
      worst = name;
    }
  }
  double geometric_mean() const { return looping > 0 ? std::exp(log_sum / looping) : 1.0; }
};

struct Totals {
  PassRatios passes;
  std::int64_t ours_reaction = 0, theirs_reaction = 0;
  int reactions = 0;
  ReactionVerdicts slower_reactions;
  std::int64_t ours_first = 0, theirs_first = 0;
  int firsts = 0, slower_firsts = 0;
  std::int64_t ours_short = 0, theirs_short = 0;
  int shorts = 0;
  std::int64_t ours_instructions = 0, theirs_instructions = 0;
  int more_instructions = 0, busy = 0;
  std::int64_t ours_ended = 0, theirs_ended = 0;  // programs that end by themselves
  int ended = 0, more_work = 0;
  double ours_latency = 0, theirs_latency = 0;
  int later = 0, unlike = 0, events = 0;
  long o2_bytes = 0, os_bytes = 0, nqc_bytes = 0;
  int o2_larger = 0, os_larger = 0, programs = 0;
};


void print_corpus(Totals& t, bool trace) {
  std::cout << "Corpus programs under the built-in scenarios, 2 ms per instruction, 20 s each\n";
  std::cout << fmt::format("{:<22} {:>21} {:>21} {:>20} {:>13} {:>17}\n", "", "instructions per pass",
                           "reaction (instr.)", "instructions (20 s)", "latency (ms)", "bytes");
  std::cout << fmt::format("{:<22} {:>7} {:>7} {:>5} {:>7} {:>7} {:>5} {:>8} {:>8} {:>5} {:>7} {:>5} {:>5} {:>5} {:>5}\n",
                           "program", "rcxc", "nqc", "ratio", "rcxc", "nqc", "ratio", "rcxc", "nqc", "ratio", "rcxc",
                           "ratio", "-O2", "-Os", "nqc");
  for (const auto& f : corpus_files()) {
    auto theirs = rcx::semtest::compile_with_nqc("nqc", f.string());
    auto bytes = nqc_bytes(f);
    auto o2 = ours(f, rcxc::ir::OptLevel::O2);
    auto os = ours(f, rcxc::ir::OptLevel::Os);
    if (!theirs.image || !bytes || !o2 || !os) continue;
    Speed s = measure_speed(o2->image, *theirs.image, {trace, f.filename().string()});
    ++t.programs;
    double ours_pass = per_pass(s.ours_pass_instructions, s.ours_passes);
    double theirs_pass = per_pass(s.theirs_pass_instructions, s.theirs_passes);
    t.passes.add(s, f.filename().string());
    t.ours_reaction += s.ours_reaction;
    t.theirs_reaction += s.theirs_reaction;
    t.reactions += s.reactions;
    t.slower_reactions.add(s, f.filename().string());
    t.ours_first += s.ours_first;
    t.theirs_first += s.theirs_first;
    t.firsts += s.firsts;
    t.slower_firsts += s.ours_first > s.theirs_first;
    t.ours_short += s.ours_short;
    t.theirs_short += s.theirs_short;
    t.shorts += s.shorts;
    if (s.busy) {
      ++t.busy;
    } else {
      t.ours_instructions += s.ours_instructions;
      t.theirs_instructions += s.theirs_instructions;
      t.more_instructions += s.ours_instructions > s.theirs_instructions;
    }
    if (s.ended) {
      t.ours_ended += s.ours_work;
      t.theirs_ended += s.theirs_work;
      t.more_work += s.ours_work > s.theirs_work;
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
    auto cell = [](double v, bool have) { return have ? fmt::format("{:.2f}", v) : std::string("-"); };
    std::cout << fmt::format(
        "{:<22} {:>7} {:>7} {:>5} {:>7} {:>7} {:>5} {:>8} {:>8} {:>5.2f} {:>7.0f} {:>5.2f} {:>5} {:>5} {:>5}{}{}\n",
        f.filename().string(), cell(ours_pass, ours_pass > 0), cell(theirs_pass, theirs_pass > 0),
        cell(ratio(ours_pass, theirs_pass), ours_pass > 0 && theirs_pass > 0), s.ours_reaction, s.theirs_reaction,
        cell(ratio(static_cast<double>(s.ours_reaction), static_cast<double>(s.theirs_reaction)), s.reactions > 0),
        s.ours_instructions, s.theirs_instructions,
        ratio(static_cast<double>(s.ours_instructions), static_cast<double>(s.theirs_instructions)), s.ours_latency_ms,
        ratio(s.ours_latency_ms, s.theirs_latency_ms), o2->code_bytes, os->code_bytes, *bytes,
        s.busy ? "  busy" : s.ended ? "  ends" : "", s.behaves_alike ? "" : "  (events differ at 2 ms)");
  }
}

struct KindTotals {
  long o2 = 0, os = 0, nqc = 0;
  int programs = 0;
};

struct SizeTotals {
  long o2 = 0, os = 0, nqc = 0;
  int o2_larger = 0, os_larger = 0, programs = 0;
  std::vector<std::string> larger;  // "kind seed: -O2 / -Os vs nqc bytes"
  std::vector<std::pair<std::string, KindTotals>> kinds;
  // The work of the generated programs that end without polling (every
  // kind but the two-task one, whose tasks poll a timer): all instructions
  // of the -O2 code and of nqc's, with no input.
  std::int64_t ours_work = 0, theirs_work = 0;
  int worked = 0;
  std::vector<std::string> more_work_names;
};

// The instructions `image` executes with no input until it ends (nullopt:
// still running after 20 s).
std::optional<std::int64_t> work(const rcx::Image& image) {
  auto m = rcx::run_scenario(image, {"none", {}}, kBrickInstructionUs, 1, kRunUs);
  if (m.stop().kind != rcx::StopKind::Ended) return std::nullopt;
  return m.instructions_executed();
}

// Generated programs of several kinds, the same seeds every run.
SizeTotals generated_sizes() {
  rcxc::bench::ScratchDir dir("rcxc-speed");
  fs::path file = dir.path / "generated.nqc";
  SizeTotals t;
  auto add = [&](const std::string& text, const std::string& name) {
    std::ofstream(file) << text;
    auto b = nqc_bytes(file);
    auto o2 = ours(file, rcxc::ir::OptLevel::O2);
    auto os = ours(file, rcxc::ir::OptLevel::Os);
    if (!b || !o2 || !os) return;
    std::string kind = name.substr(0, name.rfind(' '));
    if (t.kinds.empty() || t.kinds.back().first != kind) t.kinds.push_back({kind, {}});
    auto& k = t.kinds.back().second;
    k.o2 += o2->code_bytes;
    k.os += os->code_bytes;
    k.nqc += *b;
    ++k.programs;
    if (kind != "two tasks") {
      auto theirs = rcx::semtest::compile_with_nqc("nqc", file.string());
      auto a = work(o2->image);
      auto w = theirs.image ? work(*theirs.image) : std::nullopt;
      if (a && w) {
        t.ours_work += *a;
        t.theirs_work += *w;
        if (*a > *w) t.more_work_names.push_back(fmt::format("{}: {} vs {} instructions", name, *a, *w));
        ++t.worked;
      }
    }
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
  for (unsigned seed = 1; seed <= 100; ++seed) add(Generator(seed).program(), fmt::format("motors {}", seed));
  for (unsigned seed = 1; seed <= 100; ++seed) add(TwoTaskGenerator(seed).program(), fmt::format("two tasks {}", seed));
  for (unsigned seed = 1; seed <= 100; ++seed)
    add(CallNeighbourGenerator(seed).program(), fmt::format("calls {}", seed));
  return t;
}

// Robot control loops from a generator (tests/support/random_programs.h,
// ReactiveGenerator: programs never used to tune the passes), measured as
// the corpus is: per pass and per reaction, at -O2, against nqc's code.
struct ReactiveTotals {
  PassRatios passes;
  int programs = 0, unlike = 0;
  std::int64_t ours_reaction = 0, theirs_reaction = 0;
  int reactions = 0;
  ReactionVerdicts slower_reactions;
  std::int64_t ours_short = 0, theirs_short = 0;
  int shorts = 0;
};

ReactiveTotals generated_reactive(int count, bool trace) {
  // RCXC_BENCH_PROGRAMS names a folder to write the programs into and keep
  // (reactive1.nqc ...); otherwise a temporary one.
  const char* keep = std::getenv("RCXC_BENCH_PROGRAMS");
  std::optional<rcxc::bench::ScratchDir> scratch;
  fs::path dir = keep && *keep ? fs::path(keep) : scratch.emplace("rcxc-reactive").path;
  fs::create_directories(dir);
  ReactiveTotals t;
  for (int seed = 1; seed <= count; ++seed) {
    fs::path file = dir / fmt::format("reactive{}.nqc", seed);
    std::ofstream(file) << rcxc::test::ReactiveGenerator(static_cast<unsigned>(seed)).program();
    auto theirs = rcx::semtest::compile_with_nqc("nqc", file.string());
    auto o2 = ours(file, rcxc::ir::OptLevel::O2);
    if (!theirs.image || !o2) continue;
    Speed s = measure_speed(o2->image, *theirs.image, {trace, fmt::format("reactive {}", seed)});
    ++t.programs;
    t.unlike += !s.behaves_alike;
    t.passes.add(s, fmt::format("reactive {}", seed));
    t.ours_reaction += s.ours_reaction;
    t.theirs_reaction += s.theirs_reaction;
    t.reactions += s.reactions;
    t.ours_short += s.ours_short;
    t.theirs_short += s.theirs_short;
    t.shorts += s.shorts;
    t.slower_reactions.add(s, fmt::format("reactive {}", seed), s.behaves_alike ? "" : " (events differ at 2 ms)");
    if (trace)
      std::cerr << fmt::format("reactive {}: per pass {:.2f} vs {:.2f}, reaction {} vs {} instructions\n", seed,
                               per_pass(s.ours_pass_instructions, s.ours_passes),
                               per_pass(s.theirs_pass_instructions, s.theirs_passes), s.ours_reaction,
                               s.theirs_reaction);
  }
  return t;
}

// CPU time of compiling every corpus program `rounds` times with `command`
// (FILE replaced by the program), as processes.
double compile_cpu(const std::string& command, const std::vector<fs::path>& files, int rounds) {
  double before = children_cpu_seconds();
  for (int r = 0; r < rounds; ++r)
    for (const auto& f : files) {
      std::string cmd = std::regex_replace(command, std::regex("FILE"), "'" + f.string() + "'");
      if (std::system((cmd + " >/dev/null 2>&1").c_str()) == -1) return 0;
    }
  return children_cpu_seconds() - before;
}

fs::path rcxc_binary(const char* argv0) { return fs::absolute(argv0).parent_path().parent_path() / "rcxc"; }

}  // namespace

int main(int, char** argv) {
  // Any program nqc compiles will do: a folder from elsewhere may begin with one nqc refuses,
  // which the table below leaves out as it leaves out every such program.
  const auto files = corpus_files();
  if (std::none_of(files.begin(), files.end(), [](const fs::path& f) { return nqc_bytes(f).has_value(); })) {
    std::cout << "speed_bench: needs the corpus (" << corpus_dir().string() << ") and nqc on PATH\n";
    return 0;
  }
  const char* trace_env = std::getenv("RCXC_SPEED_TRACE");
  bool trace = trace_env && *trace_env;
  Totals t;
  print_corpus(t, trace);
  SizeTotals g = generated_sizes();
  ReactiveTotals r = generated_reactive(200, trace);
  const int rounds = 5;
  double rcxc_cpu = compile_cpu(rcxc_binary(argv[0]).string() + " compile FILE -o /dev/null", corpus_files(), rounds);
  double nqc_cpu = compile_cpu("nqc -Trcx -O/dev/null FILE", corpus_files(), rounds);
  int compiles = rounds * static_cast<int>(corpus_files().size());

  std::cout << "\nAgainst nqc (rcxc / nqc; lower is better), at the default level (-O2)\n";
  std::cout << fmt::format("  instructions per loop pass  {:.3f}  (geometric mean over {} programs that loop; {} slower "
                           "per pass; highest ratio {:.3f}, {})\n",
                           t.passes.geometric_mean(), t.passes.looping, t.passes.slower, t.passes.worst_ratio,
                           t.passes.worst);
  std::cout << fmt::format("  reaction, in instructions   {:.3f}  ({} vs {} instructions from {} input changes to the "
                           "output change each caused, over {} input timings; {} programs slower, {} more within the "
                           "noise of the timings)\n",
                           ratio(static_cast<double>(t.ours_reaction), static_cast<double>(t.theirs_reaction)),
                           t.ours_reaction, t.theirs_reaction, t.reactions, input_phases(), t.slower_reactions.slower,
                           t.slower_reactions.within_noise);
  for (const auto& l : t.slower_reactions.names) std::cout << "    reacts later than nqc's: " << l << "\n";
  std::cout << fmt::format("    of them within {} instructions  {:.3f}  ({} vs {} instructions from {} input changes)\n",
                           kShortReaction, ratio(static_cast<double>(t.ours_short), static_cast<double>(t.theirs_short)),
                           t.ours_short, t.theirs_short, t.shorts);
  std::cout << fmt::format("    to the first event after  {:.3f}  ({} vs {} instructions from {} input changes to the "
                           "first event after each, caused or not; {} programs slower)\n",
                           ratio(static_cast<double>(t.ours_first), static_cast<double>(t.theirs_first)),
                           t.ours_first, t.theirs_first, t.firsts, t.slower_firsts);
  std::cout << fmt::format("  work of programs that end   {:.3f}  ({} vs {} instructions, polls in place left out, over "
                           "{} programs; {} execute more)\n",
                           ratio(static_cast<double>(t.ours_ended), static_cast<double>(t.theirs_ended)),
                           t.ours_ended, t.theirs_ended, t.ended, t.more_work);
  std::cout << "  over the fixed 20 s (the old measure: waits and polls fill the time whatever the code)\n";
  std::cout << fmt::format("  executed instructions   {:.3f}  ({} vs {} over {} programs that wait; {} more than "
                           "nqc's; {} busy programs left out)\n",
                           ratio(static_cast<double>(t.ours_instructions), static_cast<double>(t.theirs_instructions)),
                           t.ours_instructions, t.theirs_instructions, t.programs - t.busy, t.more_instructions,
                           t.busy);
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
  for (const auto& [kind, k] : g.kinds)
    std::cout << fmt::format("    {:<12} {:.3f} at -O2, {:.3f} at -Os  ({} / {} vs {} bytes, {} programs)\n", kind,
                             ratio(static_cast<double>(k.o2), static_cast<double>(k.nqc)),
                             ratio(static_cast<double>(k.os), static_cast<double>(k.nqc)), k.o2, k.os, k.nqc,
                             k.programs);
  for (const auto& l : g.larger) std::cout << "    larger than nqc's: " << l << "\n";
  std::cout << fmt::format("  work of generated programs  {:.3f}  ({} vs {} instructions at -O2, {} programs that "
                           "end without polling; {} execute more than nqc's)\n",
                           ratio(static_cast<double>(g.ours_work), static_cast<double>(g.theirs_work)), g.ours_work,
                           g.theirs_work, g.worked, g.more_work_names.size());
  for (const auto& l : g.more_work_names) std::cout << "    more than nqc's: " << l << "\n";
  std::cout << fmt::format("  generated control loops     {:.3f} per pass (geometric mean over {} programs, {} slower "
                           "per pass), reaction {:.3f} ({} vs {} instructions from {} input changes to the output "
                           "change each caused, over {} input timings, {} programs slower and {} more within the noise of the "
                           "timings; within {} instructions {:.3f} "
                           "over {} changes); "
                           "{} of {} behave differently at 2 ms\n",
                           r.passes.geometric_mean(), r.passes.looping, r.passes.slower,
                           ratio(static_cast<double>(r.ours_reaction), static_cast<double>(r.theirs_reaction)),
                           r.ours_reaction, r.theirs_reaction, r.reactions, input_phases(), r.slower_reactions.slower,
                           r.slower_reactions.within_noise, kShortReaction,
                           ratio(static_cast<double>(r.ours_short), static_cast<double>(r.theirs_short)), r.shorts,
                           r.unlike, r.programs);
  for (const auto& l : r.slower_reactions.names) std::cout << "    reacts later than nqc's: " << l << "\n";
  std::cout << fmt::format("  compile time (CPU)      {:.3f}  ({:.1f} vs {:.1f} ms per corpus program, as processes)\n",
                           ratio(rcxc_cpu, nqc_cpu), rcxc_cpu * 1000 / compiles, nqc_cpu * 1000 / compiles);
  return 0;
}
