// `rcxc run prog.nqc` uses the program's own // @input and @for directives
// unless --scenario / --for say otherwise.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "tests/support/process.h"

using rcxc::test::run_rcxc;

namespace {

constexpr const char* kProgram =
    "// @input at 300ms: sensor 1 pressed\n"
    "// @for 1s\n"
    "int seen;\n"
    "task main() { SetSensor(SENSOR_1, SENSOR_TOUCH); until (SENSOR_1 == 1); seen = 1; }\n";

struct File {
  std::string dir = rcxc::test::make_temp_dir();
  std::string path = dir + "/p.nqc";
  File() { std::ofstream(path) << kProgram; }
  ~File() { std::filesystem::remove_all(dir); }
};

}  // namespace

TEST(RunSourceInputs, DirectivesDriveTheRunAndAreAnnounced) {
  File f;
  auto r = run_rcxc({"run", f.path, "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["globals"]["seen"], 1);
  EXPECT_EQ(j["stop"], "ended");
  EXPECT_NE(r.err.find("using the inputs written in"), std::string::npos) << r.err;
}

TEST(RunSourceInputs, ForOptionOverridesTheDirective) {
  File f;
  auto r = run_rcxc({"run", f.path, "--for", "200", "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["globals"]["seen"], 0);  // cut at 200 ms, before the press
  EXPECT_EQ(j["stop"], "time_limit");
  EXPECT_EQ(j["time_ms"], 200);
}

TEST(RunSourceInputs, ScenarioOptionReplacesTheDirectives) {
  File f;
  std::string scenario = f.dir + "/none.toml";
  std::ofstream(scenario) << "# no inputs\n";
  auto r = run_rcxc({"run", f.path, "--scenario", scenario, "--for", "1000", "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["globals"]["seen"], 0);
  EXPECT_EQ(r.err.find("using the inputs"), std::string::npos) << r.err;
}

// A test program's // @options compile it for `rcxc run` as for `rcxc test`:
// here a -D the program needs (without it the program does not compile) and
// an -I to a folder next to it; the command line's -D comes first, the
// file's after it.
TEST(RunSourceInputs, OptionsDirectiveCompilesTheRun) {
  File f;
  std::filesystem::create_directory(f.dir + "/inc");
  std::ofstream(f.dir + "/inc/speed.nqh") << "#define SPEED_OF(x) ((x) * 2)\n";
  std::string program = f.dir + "/o.nqc";
  std::ofstream(program) << "// @options -Iinc -DSPEED=3\n"
                            "#include \"speed.nqh\"\n"
                            "int v;\n"
                            "task main() { v = SPEED_OF(SPEED); }\n";
  auto r = run_rcxc({"run", program, "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["globals"]["v"], 6);
  EXPECT_NE(r.err.find("using the compiler options written in"), std::string::npos) << r.err;
}

TEST(RunSourceInputs, BadOptionsDirectiveIsAnErrorAtItsLine) {
  File f;
  std::string program = f.dir + "/bad.nqc";
  std::ofstream(program) << "int v;\n// @options -Ofast\ntask main() { v = 1; }\n";
  auto r = run_rcxc({"run", program});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.nqc:2: error: bad @options"), std::string::npos) << r.err;
}

// A directive with a mistake (`@for 3 s`) made the run drop every
// directive without a word: the inputs never came and the run took the
// default minute. It still runs without them, and says so.
// A source over the 1 MiB cap was said to have directives with errors
// (the directive reader cannot read it either): only the cap is said.
TEST(RunSourceInputs, AFileTooLargeToReadIsNotBlamedOnItsDirectives) {
  std::string dir = rcxc::test::make_temp_dir();
  std::string path = dir + "/big.nqc";
  std::ofstream(path) << kProgram << std::string(1100 * 1024, '\n');
  auto r = run_rcxc({"run", path});
  std::filesystem::remove_all(dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("larger than a source file may be (1 MiB)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("directives"), std::string::npos) << r.err;
}

TEST(RunSourceInputs, DirectivesWithErrorsAreNotUsedAndSaidSo) {
  std::string dir = rcxc::test::make_temp_dir();
  std::string path = dir + "/p.nqc";
  std::ofstream(path) << "// @for 1 s\n" << kProgram;
  auto r = run_rcxc({"run", path, "--report", "json"});
  std::filesystem::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("the // @ directives in " + path + " have errors and are not used (rcxc test " + path),
            std::string::npos)
      << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["stop"], "time_limit");
}
