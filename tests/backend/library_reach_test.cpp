// The frontend parses and checks only the standard-library functions a
// program reaches (frontend/frontend.cpp, for startup time). Whatever it
// leaves out, the compiler's answer must be the one the whole library
// gives: the same image, the same messages, on every program the project
// has, the corpus and generated ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "backend/compile.h"
#include "rcx/image.h"
#include "tests/support/process.h"
#include "tests/support/random_programs.h"

namespace rcxc {
namespace {

namespace fs = std::filesystem;

struct Result {
  std::vector<std::uint8_t> image;
  std::vector<std::string> messages;
  ir::Log log;
};

Result compile(const std::string& name, const std::string& text, bool whole_library,
               ir::OptLevel level = ir::OptLevel::O2) {
  frontend::Options options;
  options.whole_library = whole_library;
  SourceManager sm;
  Diagnostics diags;
  Result r;
  if (auto out = backend::compile_source(name, text, options, level, sm, diags, r.log))
    r.image = rcx::write_image(out->image);
  for (const auto& d : diags.all()) r.messages.push_back(render_text(d, sm));
  return r;
}

void expect_same(const std::string& name, const std::string& text) {
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    Result reached = compile(name, text, false, level), whole = compile(name, text, true, level);
    EXPECT_EQ(reached.image, whole.image) << name;
    EXPECT_EQ(reached.messages, whole.messages) << name;
    EXPECT_EQ(reached.log, whole.log) << name;
  }
}

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Only the reached functions are parsed: a program calling OnFwd gets OnFwd
// and what it calls, not PlaySound.
TEST(LibraryReach, OnlyReachedFunctionsAreParsed) {
  auto functions = [](bool whole_library) {
    frontend::Options options;
    options.whole_library = whole_library;
    SourceManager sm;
    Diagnostics diags;
    auto program = frontend::parse_source("t.nqc", "task main() { OnFwd(OUT_A); }", options, sm, diags);
    EXPECT_TRUE(program && diags.all().empty());
    std::vector<std::string> names;
    if (program)
      for (const auto& f : program->functions) names.push_back(f.name);
    return names;
  };
  auto reached = functions(false), whole = functions(true);
  auto has = [](const std::vector<std::string>& v, const char* n) { return std::count(v.begin(), v.end(), n) > 0; };
  for (const char* needed : {"OnFwd", "Fwd", "On", "SetDirection", "SetOutput"}) EXPECT_TRUE(has(reached, needed)) << needed;
  EXPECT_FALSE(has(reached, "PlaySound"));
  EXPECT_TRUE(has(whole, "PlaySound"));
  EXPECT_LT(reached.size() * 4, whole.size());
}

// The argument that the two agree rests on this: the library alone, every
// function parsed and checked, has nothing to say.
TEST(LibraryReach, TheWholeLibraryHasNoDiagnostics) {
  Result r = compile("empty.nqc", "task main() {}\n", true);
  EXPECT_TRUE(r.messages.empty()) << r.messages.front();
}

// Names the program defines itself, misspells or reaches through macros.
TEST(LibraryReach, SameAnswerOnEdgeCases) {
  const char* programs[] = {
      "task main() { OnFwd(OUT_A); }",
      "void OnFwd(int x) { } task main() { OnFwd(1); }",           // redefinition: an error
      "int PlaySound; task main() { PlaySound = 1; }",             // a variable named like one
      "task main() { OnFwrd(OUT_A); }",                            // did you mean
      "task main() { int x; OnFwd(OUT_A); }",                      // a warning, no error
      "#define GO OnRev(OUT_C)\ntask main() { GO; }",              // reached through a macro
      "task main() { SetSensor(SENSOR_1, SENSOR_TOUCH); until (SENSOR_1 == 1); Off(OUT_A); }",
      "task main() { PlaySound(SOUND_UP) }",                       // a syntax error
  };
  for (const char* p : programs) expect_same("edge.nqc", p);
}

TEST(LibraryReach, SameAnswerOnEverySemanticTestAndExample) {
  int n = 0;
  for (const char* dir : {"tests/semantic", "examples"})
    for (const auto& path : test::nqc_programs_under((fs::path(RCXC_SOURCE_DIR) / dir).string())) {
      expect_same(path, read(path));
      ++n;
    }
  EXPECT_GT(n, 300);
}

TEST(LibraryReach, SameAnswerOnTheCorpus) {
  auto files = test::nqc_programs_under(RCXC_CORPUS_DIR);
  if (files.empty()) GTEST_SKIP() << "no corpus at " << RCXC_CORPUS_DIR;
  for (const auto& path : files) expect_same(path, read(path));
}

TEST(LibraryReach, SameAnswerOnRandomPrograms) {
  for (unsigned seed = 1; seed <= 30; ++seed) {
    expect_same("random.nqc", test::Generator(seed).program());
    expect_same("two_tasks.nqc", test::TwoTaskGenerator(seed).program());
    expect_same("neighbours.nqc", test::CallNeighbourGenerator(seed).program());
  }
}

}  // namespace
}  // namespace rcxc
