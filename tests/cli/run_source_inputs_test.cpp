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
