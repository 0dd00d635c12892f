// Real programs: every corpus file that `nqc -Trcx` accepts must pass the
// frontend with no error; the ones nqc rejects must be rejected too. The
// corpus is read from RCXC_CORPUS_DIR and the test skips when it is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "tests/frontend/frontend_test_util.h"
#include "tests/support/process.h"

using namespace rcxc;
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> corpus_files() {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(RCXC_CORPUS_DIR, ec)) return files;
  for (const auto& e : fs::recursive_directory_iterator(RCXC_CORPUS_DIR, ec))
    if (e.path().extension() == ".nqc") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

bool have_nqc() {
  for (const char* dir : {"/usr/bin", "/usr/local/bin"})
    if (fs::exists(fs::path(dir) / "nqc")) return true;
  return false;
}

// What nqc 3.1 says about the corpus when nqc itself is not installed
// (learned by running `nqc -Trcx` on each file): these two are rejected,
// 01_errors.nqc on purpose (a tutorial about errors), 03_variables.nqc
// because the RCX has no arrays.
const std::set<std::string> kRejectedByNqc = {"01_errors.nqc", "03_variables.nqc"};

bool nqc_accepts(const fs::path& file) {
  if (!have_nqc()) return kRejectedByNqc.count(file.filename().string()) == 0;
  fs::path out = fs::path(test::make_temp_dir()) / "out.rcx";
  auto r = test::run_process({"/usr/bin/nqc", "-Trcx", "-O" + out.string(), file.string()});
  fs::remove_all(out.parent_path());
  return r.exit_code == 0;
}

}  // namespace

TEST(Corpus, ProgramsNqcAcceptsPassTheFrontendAndTheOthersFail) {
  auto files = corpus_files();
  if (files.empty()) GTEST_SKIP() << "no corpus at " << RCXC_CORPUS_DIR;
  int accepted = 0;
  for (const auto& f : files) {
    SourceManager sm;
    Diagnostics diags;
    auto program = frontend::parse_program(f.string(), {}, sm, diags);
    std::string text;
    for (const auto& d : diags.all()) text += render_text(d, sm);
    if (nqc_accepts(f)) {
      ++accepted;
      EXPECT_TRUE(program.has_value()) << f << "\n" << text;
      EXPECT_EQ(diags.error_count(), 0u) << f << "\n" << text;
    } else {
      EXPECT_FALSE(program.has_value()) << f << " is rejected by nqc but passed";
    }
  }
  EXPECT_GT(accepted, 0);
}

TEST(Corpus, ProgramsUseTheStdlibAndGetTaskMain) {
  fs::path f = fs::path(RCXC_CORPUS_DIR) / "examples" / "RadarGearShifter.nqc";
  if (!fs::exists(f)) GTEST_SKIP() << "no corpus file " << f;
  SourceManager sm;
  Diagnostics diags;
  auto program = frontend::parse_program(f.string(), {}, sm, diags);
  ASSERT_TRUE(program.has_value());
  // Three tasks in source order, five globals of the program itself.
  ASSERT_EQ(program->tasks.size(), 3u);
  EXPECT_EQ(program->tasks[0].name, "main");
  EXPECT_EQ(program->tasks[1].name, "Radar");
  EXPECT_EQ(program->tasks[2].name, "GearShiftTask");
  EXPECT_EQ(program->globals.size(), 5u);
}
