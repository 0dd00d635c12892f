// `rcxc compare FILE.nqc`: compiles the program with rcxc and with nqc, runs
// both images on the emulator under the same scenarios, and reports any
// difference a robot's owner could see (runtime/compare.h), side by side.
#include <fmt/format.h>

#include <iostream>

#include "cli/commands.h"
#include "cli/external_nqc.h"
#include "cli/program_loader.h"
#include "runtime/compare.h"
#include "runtime/scenario.h"

namespace rcxc::cli {
namespace {

// Exit code when the program cannot be compared (nqc is missing or refuses
// the program); CTest reports such comparisons as skipped.
constexpr int kExitNotComparable = 3;
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
};

rcx::TimeTolerance compare_tolerance(std::int64_t instruction_us) {
  // 5 ms absolute covers 500 instructions of difference at 10 us each.
  return {instruction_us * 500, 0.005};
}

struct Scenario {
  std::string name;
  std::vector<rcx::TimedInput> inputs;
};

rcx::TimedInput at(std::int64_t ms, rcx::Input in) { return {ms * rcx::kMicrosPerMs, in}; }

// Inputs most programs react to: bumpers pressed and released, IR messages,
// light levels across the thresholds programs use, wheels turning.
std::vector<Scenario> builtin_scenarios() {
  Scenario idle{"idle", {}};
  Scenario touch{"touch and messages", {}};
  for (int s = 0; s < 3; ++s) {
    for (auto [down, up] : {std::pair{1000, 1500}, {3000, 3300}, {6000, 8000}, {12000, 12400}}) {
      touch.inputs.push_back(at(down, rcx::SensorRawInput{s, 100}));
      touch.inputs.push_back(at(up, rcx::SensorRawInput{s, 1023}));
    }
  }
  for (auto [ms, value] : {std::pair{2000, 1}, {4000, 2}, {7000, 7}, {10000, 3}})
    touch.inputs.push_back(at(ms, rcx::MessageInput{value}));
  Scenario light{"light levels and rotation", {}};
  const int levels[] = {800, 500, 300, 700, 450, 900, 350, 600, 750, 400};
  for (int i = 0; i < 10; ++i)
    for (int s = 0; s < 3; ++s) {
      light.inputs.push_back(at(i * 1000, rcx::SensorRawInput{s, levels[(i + s) % 10]}));
      light.inputs.push_back(at(i * 1000 + 500, rcx::RotationInput{s, (i + 1) * 20 * (s == 1 ? -1 : 1)}));
    }
  return {idle, touch, light};
}

rcx::Machine run_image(const rcx::Image& image, const Scenario& s, const CompareOptions& o) {
  rcx::Config config;
  config.seed = o.seed;
  config.instruction_cost_us = o.instruction_us;
  rcx::Machine m(config);
  if (auto error = m.load(0, image)) throw std::runtime_error(*error);
  for (const auto& in : s.inputs) m.schedule(in);
  m.start_program();
  m.run(o.for_ms * rcx::kMicrosPerMs);
  return m;
}

int run(const CompareOptions& o) {
  std::vector<Scenario> scenarios;
  for (const auto& path : o.scenarios) {
    auto parsed = rcx::read_scenario_file(path);
    if (auto* e = std::get_if<rcx::ScenarioError>(&parsed)) {
      std::cerr << "rcxc compare: " << e->message << "\n";
      return kExitFailure;
    }
    scenarios.push_back({path, std::get<std::vector<rcx::TimedInput>>(std::move(parsed))});
  }
  if (scenarios.empty()) scenarios = builtin_scenarios();

  auto theirs = compile_with_nqc(o.nqc, o.file);
  if (!theirs.failure.empty()) {
    std::cerr << "rcxc compare: " << theirs.failure << "\n";
    return kExitNotComparable;
  }
  if (!theirs.image) {
    std::cout << o.file << ": nqc does not compile this program; nothing to compare\n";
    return kExitNotComparable;
  }
  CompileResult ours = compile_file(o.file, {});
  if (!ours.output) {
    for (const auto& d : ours.diagnostics.all()) std::cerr << render_text(d, ours.sources);
    std::cout << o.file << ": nqc compiles this program but rcxc does not\n";
    return kExitFailure;
  }
  const rcx::Image& our_image = ours.output->image;
  int differing = 0;
  for (const auto& s : scenarios) {
    try {
      rcx::Machine a = run_image(our_image, s, o);
      rcx::Machine b = run_image(*theirs.image, s, o);
      auto cmp = rcx::compare_runs({&a, &our_image, "rcxc"}, {&b, &*theirs.image, "nqc"}, compare_tolerance(o.instruction_us));
      std::cout << (cmp.same ? "same      " : "DIFFERENT ") << o.file << " [" << s.name << "]\n";
      if (cmp.same) continue;
      ++differing;
      for (const auto& d : cmp.differences) std::cout << "  " << d << "\n";
      std::cout << cmp.side_by_side;
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
  cmd->add_option("FILE", o->file, "NQC source file")->required();
  cmd->add_option("--scenario", o->scenarios, "Scenario TOML file (repeatable); default: built-in scenarios");
  cmd->add_option("--nqc-path", o->nqc, "The nqc to compare with (path or name; default: nqc on PATH)");
  cmd->add_option("--for", o->for_ms, "Virtual milliseconds per run (default 20000)")->check(CLI::PositiveNumber);
  cmd->add_option("--seed", o->seed, "Random seed for both runs");
  cmd->add_option("--instruction-us", o->instruction_us, "Virtual time per instruction (default 10)")
      ->check(CLI::Range(1, 100000));
  cmd->callback([&exit_code, o] { exit_code = run(*o); });
}

}  // namespace rcxc::cli
