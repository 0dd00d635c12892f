// Random programs compiled without optimisation and with each level must
// do the same: the same output states at every marker (a display change
// followed by a wait, which no optimisation moves a motor command across),
// the same final outputs and variables. Fixed seeds: a failure names the
// seed and prints the program.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <sstream>

#include <fmt/format.h>

#include "backend/compile.h"
#include "runtime/image.h"
#include "runtime/vm.h"
#include "tests/support/process.h"
#include "tests/support/random_programs.h"

using namespace rcxc;

using rcxc::test::ExpressionGenerator;
using rcxc::test::Generator;
using rcxc::test::TwoTaskGenerator;

namespace {

struct Observed {
  std::vector<std::string> at_markers;  // output states when each marker showed
  std::string final;                // output states
  std::map<std::string, int> vars;  // globals that have a slot
  bool ended = false;
};

// Whether `name` is declared on the program's first line (`int a, b;`):
// the globals. Locals and parameters also name slots, but what they hold
// at the end is nobody's business.
bool is_global(const std::string& text, const std::string& name) {
  std::string first = text.substr(0, text.find('\n'));
  for (char& ch : first)
    if (ch == ',' || ch == ';') ch = ' ';
  std::istringstream words(first);
  std::string w;
  while (words >> w)
    if (w == name) return true;
  return false;
}

// The globals of two runs, where a global without a slot (no code left
// touches it) must still hold the emulator's initial 0 in the other run.
std::string differing_globals(const Observed& a, const Observed& b) {
  std::string diff;
  auto check = [&](const Observed& x, const Observed& y) {
    for (const auto& [name, value] : x.vars) {
      auto it = y.vars.find(name);
      int other = it == y.vars.end() ? 0 : it->second;
      if (other != value) diff += fmt::format(" {}: {} vs {}", name, value, other);
    }
  };
  check(a, b);
  if (diff.empty()) check(b, a);
  return diff;
}

std::string describe(const std::array<rcx::Output, rcx::kOutputs>& outs) {
  std::string s;
  for (const auto& o : outs)
    s += fmt::format("[{} {} {}]", static_cast<int>(o.mode), static_cast<int>(o.dir), o.power);
  return s;
}

std::optional<Observed> observe(const std::string& text, ir::OptLevel level, std::string& error) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  frontend::Options options;
  auto out = backend::compile_source("random.nqc", text, options, level, sm, diags, log);
  if (!out) {
    for (const auto& d : diags.all()) error += render_text(d, sm);
    return std::nullopt;
  }
  rcx::Machine m;
  if (auto err = m.load(0, out->image)) {
    error = *err;
    return std::nullopt;
  }
  m.start_program();
  m.run(120'000 * rcx::kMicrosPerMs);
  Observed seen;
  seen.ended = m.stop().kind == rcx::StopKind::Ended;
  std::array<rcx::Output, rcx::kOutputs> outs{};
  for (const auto& e : m.state().events) {
    if (e.kind == rcx::EventKind::Output) outs[static_cast<std::size_t>(e.index)] = e.output;
    if (e.kind == rcx::EventKind::Display) seen.at_markers.push_back(describe(outs));
  }
  seen.final = describe(m.state().outputs);
  for (const auto& sym : out->image.symbols)
    if (sym.type == rcx::SymbolType::Variable && is_global(text, sym.name)) seen.vars[sym.name] = m.state().vars[sym.index];
  return seen;
}

}  // namespace

TEST(RandomPrograms, EveryOptimisationLevelBehavesAsUnoptimised) {
  for (unsigned seed = 1; seed <= 300; ++seed) {
    std::string text = Generator(seed).program();
    std::string error;
    auto reference = observe(text, ir::OptLevel::O0, error);
    if (!reference && error.find("bytes of program memory") != std::string::npos) continue;  // too large unoptimised
    ASSERT_TRUE(reference) << "seed " << seed << ": " << error << "\n" << text;
    for (auto level : {ir::OptLevel::O1, ir::OptLevel::Os}) {
      auto got = observe(text, level, error);
      ASSERT_TRUE(got) << "seed " << seed << ": " << error << "\n" << text;
      ASSERT_EQ(got->at_markers, reference->at_markers) << "seed " << seed << "\n" << text;
      ASSERT_EQ(got->final, reference->final) << "seed " << seed << "\n" << text;
      ASSERT_EQ(differing_globals(*got, *reference), "") << "seed " << seed << "\n" << text;
    }
  }
}

TEST(RandomPrograms, TwoTasksInTurnsBehaveAsUnoptimised) {
  for (unsigned seed = 1; seed <= 300; ++seed) {
    std::string text = TwoTaskGenerator(seed).program();
    std::string error;
    auto reference = observe(text, ir::OptLevel::O0, error);
    ASSERT_TRUE(reference) << "seed " << seed << ": " << error << "\n" << text;
    for (auto level : {ir::OptLevel::O1, ir::OptLevel::Os}) {
      auto got = observe(text, level, error);
      ASSERT_TRUE(got) << "seed " << seed << ": " << error << "\n" << text;
      ASSERT_EQ(got->at_markers, reference->at_markers) << "seed " << seed << "\n" << text;
      ASSERT_EQ(got->final, reference->final) << "seed " << seed << "\n" << text;
      ASSERT_EQ(differing_globals(*got, *reference), "") << "seed " << seed << "\n" << text;
    }
  }
}

TEST(RandomPrograms, ExpressionsComputeTheSameAtEveryLevel) {
  int compared = 0;
  for (unsigned seed = 1; seed <= 400; ++seed) {
    std::string text = ExpressionGenerator(seed).program();
    std::string error;
    auto reference = observe(text, ir::OptLevel::O0, error);
    // A constant division by zero is rightly an error; nothing to compare.
    if (!reference && error.find("division by zero in a constant expression") != std::string::npos) continue;
    if (!reference && error.find("bytes of program memory") != std::string::npos) continue;
    ASSERT_TRUE(reference) << "seed " << seed << ": " << error << "\n" << text;
    ++compared;
    ASSERT_TRUE(reference->ended) << "seed " << seed << "\n" << text;
    for (auto level : {ir::OptLevel::O1, ir::OptLevel::Os}) {
      auto got = observe(text, level, error);
      ASSERT_TRUE(got) << "seed " << seed << ": " << error << "\n" << text;
      ASSERT_EQ(got->final, reference->final) << "seed " << seed << "\n" << text;
      ASSERT_EQ(differing_globals(*got, *reference), "") << "seed " << seed << "\n" << text;
    }
  }
  EXPECT_GT(compared, 300);
}

namespace {

// The nqc on the PATH, or "" when it is not installed.
std::string find_nqc() {
  auto r = test::run_process({"/bin/sh", "-c", "command -v nqc"});
  std::string path = r.out.substr(0, r.out.find('\n'));
  return r.exit_code == 0 ? path : std::string();
}

// Final globals of the program as nqc compiles it; nullopt when nqc
// refuses it.
std::optional<Observed> observe_nqc(const std::string& nqc, const test::TempDir& dir, const std::string& text) {
  std::string src = dir.write("random.nqc", text);
  std::string image_path = dir.path + "/random.rcx";
  auto r = test::run_process({nqc, "-Trcx", "-O" + image_path, src});
  if (r.exit_code != 0) return std::nullopt;
  auto image = rcx::read_image_file(image_path);
  if (!std::holds_alternative<rcx::Image>(image)) return std::nullopt;
  const auto& img = std::get<rcx::Image>(image);
  // nqc wraps test-and-branch offsets beyond 127 bytes (docs/compiler.md):
  // only code short enough that no branch can be that long is compared.
  for (const auto& f : img.fragments)
    if (f.code.size() > 127) return std::nullopt;
  rcx::Machine m;
  if (m.load(0, img)) return std::nullopt;
  m.start_program();
  m.run(120'000 * rcx::kMicrosPerMs);
  Observed seen;
  seen.ended = m.stop().kind == rcx::StopKind::Ended;
  seen.final = describe(m.state().outputs);
  for (const auto& sym : img.symbols)
    if (sym.type == rcx::SymbolType::Variable && is_global(text, sym.name)) seen.vars[sym.name] = m.state().vars[sym.index];
  return seen;
}

}  // namespace

TEST(RandomPrograms, ExpressionsComputeWhatNqcsCodeComputes) {
  std::string nqc = find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  test::TempDir dir;
  int compared = 0;
  for (unsigned seed = 1; seed <= 1200; ++seed) {
    std::string text = ExpressionGenerator(seed, true).program();
    std::string error;
    auto ours = observe(text, ir::OptLevel::Os, error);
    if (!ours) continue;  // a constant division by zero, or too large
    auto theirs = observe_nqc(nqc, dir, text);
    if (!theirs || !theirs->ended) continue;  // nqc refuses it (e.g. out of temporaries)
    ++compared;
    ASSERT_EQ(differing_globals(*ours, *theirs), "") << "seed " << seed << "\n" << text;
  }
  EXPECT_GT(compared, 250);
}
