// Images written by the reference compiler (`nqc -Trcx -O`) for every corpus
// program load and run without faults; a few are checked against behaviour
// worked out by hand from their source. Skips when nqc or the corpus is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "rcx/image.h"
#include "runtime/vm.h"
#include "tests/support/process.h"

namespace fs = std::filesystem;

namespace {

constexpr const char* kNqc = "/usr/bin/nqc";

struct Compiled {
  bool ok = false;
  rcx::Image image;
};

Compiled compile_with_nqc(const fs::path& source, const std::string& dir) {
  std::string out = dir + "/" + source.stem().string() + ".rcx";
  auto r = rcxc::test::run_process({kNqc, "-Trcx", "-O" + out, source.string()});
  if (r.exit_code != 0) return {};
  auto image = rcx::read_image_file(out);
  if (auto* e = std::get_if<rcx::ImageError>(&image)) {
    ADD_FAILURE() << e->message;
    return {};
  }
  return {true, std::get<rcx::Image>(image)};
}

// Why the corpus tests cannot run here, or "" when they can.
std::string missing_tools() {
  if (!fs::exists(kNqc)) return "nqc is not installed";
  if (!fs::is_directory(RCXC_CORPUS_DIR)) return std::string("no corpus at ") + RCXC_CORPUS_DIR;
  return "";
}

rcx::Machine run_image(const rcx::Image& image, rcx::Micros limit_ms) {
  rcx::Machine m;
  auto error = m.load(0, image);
  EXPECT_FALSE(error) << *error;
  m.start_program();
  m.run(limit_ms * rcx::kMicrosPerMs);
  return m;
}

// Compiles tutorial/NAME.nqc with nqc and runs it for up to a minute;
// nullopt with the reason in `skip` when that cannot be done here.
std::optional<rcx::Machine> run_tutorial(const std::string& name, std::string& skip) {
  skip = missing_tools();
  fs::path source = fs::path(RCXC_CORPUS_DIR) / "tutorial" / (name + ".nqc");
  if (skip.empty() && !fs::exists(source)) skip = name + ".nqc is not in the corpus";
  if (!skip.empty()) return std::nullopt;
  std::string dir = rcxc::test::make_temp_dir();
  Compiled c = compile_with_nqc(source, dir);
  fs::remove_all(dir);
  if (!c.ok) {
    ADD_FAILURE() << "nqc could not compile " << source;
    return std::nullopt;
  }
  return run_image(c.image, 60'000);
}

}  // namespace

TEST(CorpusRun, EveryNqcImageRunsWithoutFault) {
  if (auto skip = missing_tools(); !skip.empty()) GTEST_SKIP() << skip;
  std::string dir = rcxc::test::make_temp_dir();
  int compiled = 0;
  for (const auto& entry : fs::recursive_directory_iterator(RCXC_CORPUS_DIR)) {
    if (entry.path().extension() != ".nqc") continue;
    Compiled c = compile_with_nqc(entry.path(), dir);
    if (!c.ok) continue;  // programs nqc itself rejects (tutorial error examples)
    ++compiled;
    rcx::Machine m = run_image(c.image, 30'000);
    EXPECT_NE(m.stop().kind, rcx::StopKind::Fault)
        << entry.path() << ": " << (m.stop().fault ? m.stop().fault->message : "");
  }
  fs::remove_all(dir);
  EXPECT_GT(compiled, 20);
}

TEST(CorpusRun, DatalogTutorialLogsBothVariables) {
  std::string skip;
  auto run = run_tutorial("12_datalog", skip);
  if (!run) GTEST_SKIP() << skip;
  const rcx::Machine& m = *run;
  // The program: datalog of 100, then 50 times log move_time (0, 1, ...) and
  // turn_time (50, 49, ...).
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  const auto& log = m.state().datalog;
  ASSERT_EQ(log.size(), 100u);
  EXPECT_EQ(log[0].value, 0);
  EXPECT_EQ(log[1].value, 50);
  EXPECT_EQ(log[2].value, 1);
  EXPECT_EQ(log[3].value, 49);
  EXPECT_EQ(log[99].value, 1);
}

TEST(CorpusRun, SubsTutorialTurnsAtTheExpectedTimes) {
  std::string skip;
  auto run = run_tutorial("06_subs", skip);
  if (!run) GTEST_SKIP() << skip;
  const rcx::Machine& m = *run;
  // 2 ms per instruction: pwr, dir, dir, out (A and C on at 6 ms); Wait(100)
  // at 8 ms; the call at 1008 ms; the sub's first instruction reverses C at 1010 ms.
  std::vector<rcx::Event> outs;
  for (const auto& e : m.state().events)
    if (e.kind == rcx::EventKind::Output) outs.push_back(e);
  ASSERT_GE(outs.size(), 3u);
  EXPECT_EQ(outs[0].t_us, 6'000);
  EXPECT_EQ(outs[2].t_us, 1'010'000);
  EXPECT_EQ(outs[2].index, 2);
  EXPECT_EQ(outs[2].output.dir, rcx::Direction::Reverse);
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
}
