// `rcxc compare FILE.nqc`: compiles the program with rcxc and with nqc, runs
// both images on the emulator under the same scenarios, and reports any
// difference a robot's owner could see (verify/compare.h), side by side.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

#include "cli/commands.h"
#include "verify/external_nqc.h"
#include "cli/program_loader.h"
#include "verify/compare.h"
#include "runtime/scenario.h"
#include "verify/scenarios.h"

namespace rcxc::cli {
namespace {

constexpr std::int64_t kCompareInstructionUs = 10;

struct CompareOptions {
  std::string file;
  std::vector<std::string> scenarios;
  std::string nqc = "nqc";
  std::int64_t for_ms = 20'000;
  std::uint64_t seed = 1;
  // Both compilers' code runs with a tiny instruction time, so that what
  // remains of a difference in instruction counts is far below the
  // tolerance while the programs' own waits are exact.
  std::int64_t instruction_us = kCompareInstructionUs;
  CompilerArgs compiler;  // given to both compilers (nqc: all but -O)
  bool all_rows = false;  // the whole side by side, not the rows around the first difference
};

// Rows of the side by side shown before and after the first that differs:
// a program that switches an output on every pass shows tens of thousands
// of events, and the first difference is what explains the others.
constexpr std::size_t kRowsBefore = 10, kRowsAfter = 30;

// The header and the rows around event row `first` (the first that differs
// but for the time), with how many rows were left out on each side.
std::string rows_around(const std::string& side_by_side, std::size_t first_event_row) {
  std::vector<std::string_view> rows;
  for (std::size_t at = 0; at < side_by_side.size();) {
    std::size_t end = side_by_side.find('\n', at);
    if (end == std::string::npos) end = side_by_side.size();
    rows.push_back(std::string_view(side_by_side).substr(at, end - at));
    at = end + 1;
  }
  if (rows.size() <= 1 + kRowsBefore + kRowsAfter + 1) return side_by_side;
  std::size_t first = std::min(first_event_row + 1, rows.size() - 1);
  std::size_t from = first > 1 + kRowsBefore ? first - kRowsBefore : 1;
  std::size_t to = std::min(rows.size(), first + kRowsAfter + 1);
  std::string out = std::string(rows[0]) + "\n";
  if (from > 1) out += fmt::format("  ... {} row{} before\n", from - 1, from - 1 == 1 ? "" : "s");
  for (std::size_t i = from; i < to; ++i) out += std::string(rows[i]) + "\n";
  if (to < rows.size())
    out += fmt::format("  ... {} row{} after (--all-rows shows every row)\n", rows.size() - to,
                       rows.size() - to == 1 ? "" : "s");
  return out;
}

// The first event row of a side by side that differs at all, its time
// included (every row both runs show alike but for the time is unmarked
// only when the times agree too).
std::size_t first_marked_row(const std::string& side_by_side) {
  std::size_t row = 0;
  for (std::size_t at = side_by_side.find('\n'); at != std::string::npos && at + 1 < side_by_side.size();
       at = side_by_side.find('\n', at + 1), ++row)
    if (side_by_side[at + 1] == '*') return row;
  return row;
}

rcx::TimeTolerance compare_tolerance(std::int64_t instruction_us) {
  // 5 ms absolute covers 500 instructions of difference at 10 us each; a
  // running output's direction or power held for up to 5 instructions is
  // the order of a few commands (nqc switches on, then sets direction).
  return {instruction_us * 500, 0.005, instruction_us * 5};
}

using Scenario = rcx::NamedScenario;

rcx::Machine run_image(const rcx::Image& image, const Scenario& s, const CompareOptions& o, rcx::Micros until_us) {
  return rcx::run_scenario(image, s, o.instruction_us, o.seed, until_us);
}

// The brick takes about 2 ms per instruction (docs/emulator.md); the runs
// here take o.instruction_us, so a time difference is so many instructions.
constexpr double kBrickInstructionMs = rcx::kDefaultInstructionCostUs / 1000.0;

// "timing: ..." for the matched events of one scenario: how much sooner (or
// later) rcxc's code acted, in instructions and in brick time.
std::string timing_note(const rcx::RunComparison& cmp, const CompareOptions& o) {
  auto d = rcx::timing_difference(cmp.matched);
  if (d.events == 0) return "";
  double mean = d.mean_sooner_us / static_cast<double>(o.instruction_us);
  double worst = static_cast<double>(d.worst_later_us) / static_cast<double>(o.instruction_us);
  std::string out = fmt::format("; timing over {} matched event{}: rcxc's code acted {:.1f} instructions {} on "
                                "average ({:.1f} ms on the brick)",
                                d.events, d.events == 1 ? "" : "s", std::abs(mean), mean >= 0 ? "sooner" : "later",
                                std::abs(mean) * kBrickInstructionMs);
  if (d.worst_later_us > 0)
    out += fmt::format(", at worst {:.0f} later ({:.0f} ms)", worst, worst * kBrickInstructionMs);
  return out;
}

// "rcxc's code up to 12 ms sooner" (and "... up to 3 ms later") for runs that
// differ in timing only, in the run's own time.
std::string timing_only_note(const rcx::RunComparison& cmp) {
  std::string out;
  auto ms = [](rcx::Micros us) { return fmt::format("{:.1f} ms", static_cast<double>(us) / rcx::kMicrosPerMs); };
  if (cmp.most_sooner_us > 0) out = "rcxc's code up to " + ms(cmp.most_sooner_us) + " sooner";
  if (cmp.most_later_us > 0) out += (out.empty() ? "rcxc's code up to " : " and up to ") + ms(cmp.most_later_us) + " later";
  return out;
}

// Runs that differ in timing only, run again at a tenth of the instruction
// time: does the difference shrink with it, as one of speed does
// (verify/compare.h, timing_cause)? With the first runs' tolerance, so a
// difference of speed parts ten times later or not at all.
rcx::TimingVerdict timing_cause(const rcx::Image& ours, const rcx::Image& theirs, const Scenario& s,
                                const CompareOptions& o, rcx::TimeTolerance tolerance,
                                const std::vector<std::string>& globals, const rcx::RunComparison& cmp) {
  const rcx::Micros tenth = o.instruction_us / 10;
  if (tenth < 1) return {rcx::TimingCause::Undecided, "--instruction-us below 10 leaves no tenth to run at"};
  // Only as far as the latest event that parted (and its allowance): at the
  // shorter time the same events come no later, and a run switching an
  // output on every pass shows ten times the events in the same time.
  rcx::Micros parted_us = 0;
  for (const auto& stream : cmp.streams)
    if (stream.parted_at) parted_us = std::max({parted_us, stream.parted_times.a_us, stream.parted_times.b_us});
  const rcx::Micros end = std::min(o.for_ms * rcx::kMicrosPerMs,
                                   parted_us + tolerance.absolute_us +
                                       static_cast<rcx::Micros>(tolerance.relative * static_cast<double>(parted_us)) + 1);
  rcx::Machine a = rcx::run_scenario(ours, s, tenth, o.seed, end);
  rcx::Machine b = rcx::run_scenario(theirs, s, tenth, o.seed, end);
  auto shorter = rcx::compare_runs({&a, &ours, "rcxc"}, {&b, &theirs, "nqc"}, tolerance, globals, rcx::SideBySide::Skip);
  return rcx::timing_cause(cmp, o.instruction_us, shorter, tenth);
}

// A program that samples an input twice a few instructions apart reacts to a
// change only if it lands between the two reads, so two compilers' code can
// react to the same input differently although neither is wrong: the
// difference is where the input fell among instructions. When runs differ,
// each group of simultaneous inputs of nqc's run is, in time order, moved by
// up to kMaxShiftInstructions instruction times (either way) until the two
// runs agree up to the group after the next one, or failing that up to the
// next input. If every group can be placed so and the
// whole runs then agree, the difference was instruction timing, which the
// comparison allows; a real difference in behaviour survives any such shift.
// Returns how many input groups had to move, or nullopt.
constexpr int kMaxShiftInstructions = 20;

std::optional<int> align_inputs(const rcx::Image& ours, const rcx::Image& theirs, const Scenario& s,
                                const CompareOptions& o, rcx::TimeTolerance tolerance,
                                const std::vector<std::string>& globals) {
  const rcx::Micros end = o.for_ms * rcx::kMicrosPerMs;
  Scenario shifted = s;
  std::stable_sort(shifted.inputs.begin(), shifted.inputs.end(),
                   [](const rcx::TimedInput& x, const rcx::TimedInput& y) { return x.at_us < y.at_us; });
  const Scenario original = shifted;
  // rcxc's run never changes (its inputs stay where they are): one per
  // horizon, and a group's wide horizon is the next group's narrow one.
  std::map<rcx::Micros, rcx::Machine> ours_to;
  auto ours_until = [&](rcx::Micros until) -> const rcx::Machine& {
    auto it = ours_to.find(until);
    if (it == ours_to.end()) it = ours_to.emplace(until, run_image(ours, original, o, until)).first;
    return it->second;
  };
  // nqc's run is the same in every trial up to the earliest time a trial
  // moves the group being placed to: it runs there once (`before`, with the
  // inputs before the group, from run_before_group) and each trial goes on
  // from a copy, with the group that starts at `first` and the inputs after it.
  auto theirs_until = [&](std::size_t first, const std::optional<rcx::Machine>& before, rcx::Micros until) {
    if (!before) return run_image(theirs, shifted, o, until);
    rcx::Machine b = *before;
    for (std::size_t n = first; n < shifted.inputs.size(); ++n) b.schedule(shifted.inputs[n]);
    b.run(until);
    return b;
  };
  // The run nqc's code makes before group [first, ...) can move, when it is
  // still running then and every input before the group lies before it.
  auto run_before_group = [&](std::size_t first) -> std::optional<rcx::Machine> {
    const rcx::Micros at = original.inputs[first].at_us - (kMaxShiftInstructions + 2) * o.instruction_us;
    auto before = shifted.inputs.begin() + static_cast<std::ptrdiff_t>(first);
    if (at <= 0 || std::any_of(shifted.inputs.begin(), before, [&](const auto& in) { return in.at_us >= at; }))
      return std::nullopt;
    rcx::Machine m = rcx::start_scenario(theirs, {shifted.inputs.begin(), before}, o.instruction_us, o.seed);
    m.run_until(at);
    // Ended, faulted or off: whole runs say where and when, as they did.
    if (m.stop().kind != rcx::StopKind::Running) return std::nullopt;
    return m;
  };
  // Moves inputs [first, last) by 0, then 1, -1, 2, -2, ... instruction
  // times until the runs agree up to `until`; false (inputs left moved by the
  // last try) when no such shift exists.
  auto place_group = [&](std::size_t first, std::size_t last, const std::optional<rcx::Machine>& before,
                         rcx::Micros until) {
    const rcx::Machine& a = ours_until(until);
    for (int k = 0; k <= kMaxShiftInstructions; ++k)
      for (int sign : {1, -1}) {
        if (k == 0 && sign < 0) continue;
        rcx::Micros shift = sign * k * o.instruction_us;
        for (std::size_t n = first; n < last; ++n)
          shifted.inputs[n].at_us = std::max<rcx::Micros>(0, original.inputs[n].at_us + shift);
        rcx::Machine b = theirs_until(first, before, until);
        if (rcx::compare_runs({&a, &ours, "rcxc"}, {&b, &theirs, "nqc"}, tolerance, globals, rcx::SideBySide::Skip)
                .same)
          return true;
      }
    return false;
  };
  int moved = 0;
  // Without inputs there is nothing to move, so nothing to explain.
  if (original.inputs.empty()) return std::nullopt;
  // Inputs from the end of the run on change nothing the runs show, and no
  // run goes past that end (--for).
  for (std::size_t i = 0; i < original.inputs.size() && original.inputs[i].at_us < end;) {
    std::erase_if(ours_to, [&](const auto& kept) { return kept.first < original.inputs[i].at_us; });
    const std::optional<rcx::Machine> before = run_before_group(i);
    std::size_t j = i;  // [i, j): inputs at the same time move together
    while (j < original.inputs.size() && original.inputs[j].at_us == original.inputs[i].at_us) ++j;
    std::size_t after_next = j;  // end of the next group
    while (after_next < original.inputs.size() && original.inputs[after_next].at_us == original.inputs[j].at_us)
      ++after_next;
    rcx::Micros horizon = std::min(end, j < original.inputs.size() ? original.inputs[j].at_us : end);
    rcx::Micros wide_horizon =
        std::min(end, after_next < original.inputs.size() ? original.inputs[after_next].at_us : end);
    // A reaction can outlast the next input (a half-second pulse begun just
    // before a sensor that program never reads changes), and a placement
    // that agrees only up to that input can leave the runs apart for good.
    // So a placement that agrees past the next group too is preferred.
    bool placed = place_group(i, j, before, wide_horizon) || place_group(i, j, before, horizon);
    if (!placed) return std::nullopt;
    moved += shifted.inputs[i].at_us != original.inputs[i].at_us;
    i = j;
  }
  // The last group was checked up to the end of the run; if nothing had to
  // move, the runs agree as they are and the caller would not have asked.
  return moved > 0 ? std::optional<int>(moved) : std::nullopt;
}

int run(const CompareOptions& o) {
  if (auto bad = bad_compiler_arguments(o.compiler)) {
    std::cerr << "rcxc compare: " << *bad << "\n";
    return kExitUsage;
  }
  if (o.file == frontend::kStandardInput) {
    std::cerr << "rcxc compare: compare needs the program in a file, which nqc compiles too (not '-', the standard "
                 "input)\n";
    return kExitUsage;
  }
  if (auto problem = special_file_problem(o.file, Takes::Files, "compare needs the program in a file, which nqc compiles too")) {
    std::cerr << "rcxc compare: " << *problem << "\n";
    return kExitFailure;
  }
  // A file that is not source (missing, a folder, an image, binary bytes)
  // is refused in rcxc compile's words before nqc is asked: nqc's refusal
  // would read as "nothing to compare" (exit 5) for what is a bad input.
  if (is_nqc_source(o.file) != true) {
    CompileResult refused = compile_file(o.file, compile_request(o.compiler));
    if (!refused.output) {
      std::cerr << render_all(refused.diagnostics, refused.sources, {});
      return kExitFailure;
    }
  }
  std::vector<Scenario> scenarios;
  for (const auto& path : o.scenarios) {
    auto parsed = rcx::read_scenario_file(path);
    if (auto* e = std::get_if<rcx::ScenarioError>(&parsed)) {
      std::cerr << "rcxc compare: " << e->message << "\n";
      return kExitFailure;
    }
    scenarios.push_back({path, std::get<std::vector<rcx::TimedInput>>(std::move(parsed))});
    if (scenarios.back().inputs.empty())
      std::cerr << "rcxc compare: note: " << path << " holds no [[input]] tables: its runs have no inputs\n";
  }
  if (scenarios.empty()) scenarios = rcx::builtin_scenarios();

  auto theirs = rcx::semtest::compile_with_nqc(o.nqc, o.file, nqc_arguments(o.compiler));
  if (!theirs.failure.empty()) {
    std::cerr << "rcxc compare: " << theirs.failure << "\n";
    return kExitNotComparable;
  }
  CompileResult ours = compile_file(o.file, compile_request(o.compiler));
  if (!theirs.image) {
    // Why neither compiles, or why nqc does not: the refusal alone says nothing.
    if (!ours.output) std::cerr << render_all(ours.diagnostics, ours.sources, {});
    for (const auto& m : theirs.messages)
      std::cerr << "nqc: " << (m.line > 0 ? fmt::format("line {}: ", m.line) : "") << m.message << "\n";
    std::cout << o.file << (ours.output ? ": nqc does not compile this program" : ": neither nqc nor rcxc compiles this program")
              << "; nothing to compare\n";
    return kExitNotComparable;
  }
  if (!ours.output) {
    std::cerr << render_all(ours.diagnostics, ours.sources, {});
    std::cout << o.file << ": nqc compiles this program but rcxc does not\n";
    return kExitFailure;
  }
  const rcx::Image& our_image = ours.output->image;
  int differing = 0;
  auto tolerance = compare_tolerance(o.instruction_us);
  for (const auto& s : scenarios) {
    try {
      rcx::Machine a = run_image(our_image, s, o, o.for_ms * rcx::kMicrosPerMs);
      rcx::Machine b = run_image(*theirs.image, s, o, o.for_ms * rcx::kMicrosPerMs);
      const rcx::RunView ours_run{&a, &our_image, "rcxc"}, theirs_run{&b, &*theirs.image, "nqc"};
      // The side by side is written only where it is shown, below: a run of
      // millions of events written twice over took gigabytes.
      auto cmp = rcx::compare_runs(ours_run, theirs_run, tolerance, ours.globals, rcx::SideBySide::Skip);
      for (const auto& [run, who] : {std::pair{&a, "rcxc"}, std::pair{&b, "nqc"}})
        if (run->stop().kind == rcx::StopKind::EventLimit)
          std::cerr << "rcxc compare: [" << s.name << "] " << who << "'s run stopped at "
                    << run->now_us() / rcx::kMicrosPerMs << " ms: " << rcx::event_limit_reason(*run)
                    << "; the runs are compared up to there (ask for less with --for)\n";
      if (cmp.same) {
        std::cout << "same      " << o.file << " [" << s.name << "]" << timing_note(cmp, o) << "\n";
        continue;
      }
      if (auto shifted = align_inputs(our_image, *theirs.image, s, o, tolerance, ours.globals)) {
        std::cout << "same      " << o.file << " [" << s.name << "] once " << *shifted
                  << " input time(s) moved by at most " << kMaxShiftInstructions
                  << " instruction times for nqc's code (instruction timing)\n";
        continue;
      }
      ++differing;
      auto verdict = cmp.timing_only ? timing_cause(our_image, *theirs.image, s, o, tolerance, ours.globals, cmp)
                                     : rcx::TimingVerdict{};
      if (cmp.timing_only && verdict.cause != rcx::TimingCause::NotSpeed) {
        // Every line of the side by side would differ in its time alone.
        std::cout << "DIFFERENT " << o.file << " [" << s.name << "] in timing only: the same " << cmp.in_order
                  << " events in the same order, " << timing_only_note(cmp)
                  << "; what this program shows depends on how fast its code runs (an output switched or a "
                     "sound played on every pass of a loop, a count of passes)";
        if (verdict.cause == rcx::TimingCause::Speed)
          std::cout << "; at a tenth of the instruction time the difference shrinks, as one of speed does\n";
        else
          std::cout << "; whether speed alone explains it is undecided: " << verdict.why << "\n";
        for (const auto& d : cmp.differences) std::cout << "  first: " << d << "\n";
        continue;
      }
      if (cmp.timing_only) {
        // The same events in the same order, but apart by more than speed
        // explains: the runs took other paths to them, a difference of logic.
        std::cout << "DIFFERENT " << o.file << " [" << s.name << "]: the same " << cmp.in_order
                  << " events in the same order, but not a difference of speed, which shrinks with the instruction "
                     "time: "
                  << verdict.why << "\n";
        for (const auto& d : cmp.differences) std::cout << "  " << d << "\n";
        cmp = rcx::compare_runs(ours_run, theirs_run, tolerance, ours.globals, rcx::SideBySide::Write);
        std::cout << (o.all_rows ? cmp.side_by_side : rows_around(cmp.side_by_side, first_marked_row(cmp.side_by_side)));
        continue;
      }
      std::cout << "DIFFERENT " << o.file << " [" << s.name << "]\n";
      for (const auto& d : cmp.differences) std::cout << "  " << d << "\n";
      cmp = rcx::compare_runs(ours_run, theirs_run, tolerance, ours.globals, rcx::SideBySide::Write);
      std::cout << (o.all_rows ? cmp.side_by_side : rows_around(cmp.side_by_side, cmp.first_unlike_row));
    } catch (const std::exception& e) {
      std::cout << "DIFFERENT " << o.file << " [" << s.name << "]: cannot load: " << e.what() << "\n";
      ++differing;
    }
  }
  return differing == 0 ? kExitOk : kExitFailure;
}

}  // namespace

void register_compare(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("compare", "Run a program as rcxc and as nqc compile it; report behaviour differences");
  auto o = std::make_shared<CompareOptions>();
  cmd->add_option("FILE", o->file, "NQC source file")->required()->check(not_empty());
  add_compiler_options(cmd, o->compiler);
  add_repeatable(cmd, "--scenario", o->scenarios, "Scenario TOML file (repeatable); default: built-in scenarios")->check(not_empty());
  cmd->add_option("--nqc-path", o->nqc, "The nqc to compare with (path or name; default: nqc on PATH)")->check(not_empty());
  cmd->add_option("--for", o->for_ms, "Virtual milliseconds per run (default 20000)")
      ->check(in_range(1, kLongestRunMs, "ms"));
  cmd->add_option("--seed", o->seed, "Random seed for both runs (default 1)")->check(whole_number());
  cmd->add_option("--instruction-us", o->instruction_us, "Virtual time per instruction (default 10)")
      ->check(in_range(1, 100000));
  cmd->add_flag("--all-rows", o->all_rows,
                "Show both runs' events side by side in full (default: the rows around the first difference)");
  cmd->callback([&exit_code, o] { exit_code = run(*o); });
}

}  // namespace rcxc::cli
