// `rcxc compile` end to end: diagnostics on stderr in text or JSON, exit
// codes, -E, -D/-I/-n, -Werror and -w.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/process.h"

using rcxc::test::run_rcxc;
namespace fs = std::filesystem;

namespace {

class CompileCli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = rcxc::test::make_temp_dir(); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    fs::path p = fs::path(dir_) / name;
    std::ofstream(p) << text;
    return p.string();
  }

  std::string dir_;
};

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

}  // namespace

TEST_F(CompileCli, ErrorsGoToStderrGccStyleWithExitCode1) {
  auto f = write("bad.nqc", "task main()\n{\n  x = 1;\n}\n");
  auto r = run_rcxc({"compile", f});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, f + ":3:3: error: 'x' is not declared\n    x = 1;\n    ^\n");
}

TEST_F(CompileCli, JsonDiagnosticsOnePerLine) {
  auto f = write("bad.nqc", "#define USE y\ntask main()\n{\n  int x;\n  x = USE;\n  break;\n}\n");
  auto r = run_rcxc({"compile", "--diagnostics=json", f});
  EXPECT_EQ(r.exit_code, 1);
  auto ls = lines(r.err);
  ASSERT_EQ(ls.size(), 2u) << r.err;
  auto first = nlohmann::json::parse(ls[0]);
  EXPECT_EQ(first["file"], f);
  EXPECT_EQ(first["line"], 1);
  EXPECT_EQ(first["column"], 13);
  EXPECT_EQ(first["end"]["column"], 14);
  EXPECT_EQ(first["severity"], "error");
  EXPECT_EQ(first["message"], "'y' is not declared");
  ASSERT_EQ(first["notes"].size(), 1u);
  EXPECT_EQ(first["notes"][0]["message"], "in expansion of macro 'USE'");
  EXPECT_EQ(first["notes"][0]["line"], 5);
  EXPECT_EQ(first["notes"][0]["column"], 7);
  auto second = nlohmann::json::parse(ls[1]);
  EXPECT_EQ(second["message"], "'break' outside a loop or switch");
  EXPECT_EQ(second["line"], 6);
}

TEST_F(CompileCli, WarningsDoNotFailButWerrorDoesAndMinusWSilences) {
  auto f = write("warn.nqc", "task main()\n{\n  int unused;\n}\n");
  auto plain = run_rcxc({"compile", f});
  EXPECT_NE(plain.err.find(":3:7: warning: unused variable 'unused'"), std::string::npos) << plain.err;
  EXPECT_EQ(plain.exit_code, 0) << plain.err;  // a warning alone does not fail the compile

  auto werror = run_rcxc({"compile", "-Werror", f});
  EXPECT_EQ(werror.exit_code, 1);
  EXPECT_NE(werror.err.find(":3:7: error: unused variable 'unused'"), std::string::npos) << werror.err;

  auto quiet = run_rcxc({"compile", "-w", f});
  EXPECT_EQ(quiet.err.find("unused"), std::string::npos) << quiet.err;
}

TEST_F(CompileCli, WarningsAreNamedAndTurnedOffOrPromotedByName) {
  auto f = write("two.nqc", "task main()\n{\n  int unused;\n  PlaySound(9);\n}\n");
  auto plain = run_rcxc({"compile", f});
  EXPECT_NE(plain.err.find(":3:7: warning: unused variable 'unused' [-Wunused-variable]\n"), std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find(":4:3: warning: 'PlaySound' passes 9"), std::string::npos) << plain.err;

  auto no_unused = run_rcxc({"compile", "-Wno-unused-variable", f});
  EXPECT_EQ(no_unused.exit_code, 0) << no_unused.err;
  EXPECT_EQ(no_unused.err.find("unused"), std::string::npos) << no_unused.err;
  EXPECT_NE(no_unused.err.find("[-Wrange]"), std::string::npos) << no_unused.err;

  auto range_error = run_rcxc({"compile", "-Werror=range", f});
  EXPECT_EQ(range_error.exit_code, 1);
  EXPECT_NE(range_error.err.find("warning: unused variable 'unused' [-Wunused-variable]"), std::string::npos);
  EXPECT_NE(range_error.err.find(":4:3: error: 'PlaySound' passes 9"), std::string::npos) << range_error.err;
  EXPECT_NE(range_error.err.find("[-Werror=range]"), std::string::npos) << range_error.err;

  auto json = run_rcxc({"compile", "--diagnostics=json", "-Wno-range", f});
  EXPECT_NE(json.err.find("\"code\":\"unused-variable\""), std::string::npos) << json.err;
  EXPECT_EQ(json.err.find("PlaySound"), std::string::npos) << json.err;

  auto misspelt = run_rcxc({"compile", "-Wno-unused-varaible", f});
  EXPECT_EQ(misspelt.exit_code, 2);
  EXPECT_NE(misspelt.err.find("rcxc compile: unknown warning option '-Wno-unused-varaible'; did you mean "
                              "'unused-variable'?"),
            std::string::npos)
      << misspelt.err;
}

TEST_F(CompileCli, UnknownWarningOptionIsAUsageError) {
  auto f = write("ok.nqc", "task main() { }\n");
  auto r = run_rcxc({"compile", "-Wfrob", f});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("-Wfrob"), std::string::npos);
}

TEST_F(CompileCli, PreprocessOnlyPrintsTheExpandedSource) {
  auto f = write("pp.nqc", "#define SPEED 4\nint s = SPEED * LEVEL;\ntask main() { }\n");
  auto r = run_rcxc({"compile", "-E", "-n", "-DLEVEL=2", f});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "# 2 \"" + f + "\"\nint s = 4 * 2;\ntask main() { }\n");
}

TEST_F(CompileCli, PreprocessOnlyIncludesTheStdlibUnlessMinusN) {
  auto f = write("pp.nqc", "task main() { OnFwd(OUT_A); }\n");
  auto with = run_rcxc({"compile", "-E", f});
  EXPECT_EQ(with.exit_code, 0);
  EXPECT_NE(with.out.find("rcx.nqh"), std::string::npos);
  EXPECT_NE(with.out.find("task main() { OnFwd(1); }"), std::string::npos) << with.out;
  auto without = run_rcxc({"compile", "-E", "-n", f});
  EXPECT_EQ(without.out.find("rcx.nqh"), std::string::npos);
  EXPECT_NE(without.out.find("OnFwd(OUT_A)"), std::string::npos);
}

TEST_F(CompileCli, IncludeDirectoriesAndUndefine) {
  fs::create_directories(fs::path(dir_) / "inc");
  write("inc/speeds.nqh", "#define FAST 7\n");
  auto f = write("main.nqc", "#include \"speeds.nqh\"\n#ifdef GONE\n#error GONE is defined\n#endif\n"
                             "int s = FAST;\ntask main() { }\n");
  auto missing = run_rcxc({"compile", "-E", f});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("cannot find include file 'speeds.nqh'"), std::string::npos) << missing.err;
  auto r = run_rcxc({"compile", "-E", "-I", (fs::path(dir_) / "inc").string(), "-DGONE", "-UGONE", f});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("int s = 7;"), std::string::npos) << r.out;
}

TEST_F(CompileCli, MissingFileAndDirectoryAreClearErrors) {
  auto r = run_rcxc({"compile", (fs::path(dir_) / "nope.nqc").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos) << r.err;
  auto d = run_rcxc({"compile", dir_});
  EXPECT_EQ(d.exit_code, 1);
  EXPECT_NE(d.err.find("is a directory"), std::string::npos) << d.err;
}

TEST_F(CompileCli, BadDiagnosticsFormatIsAUsageError) {
  auto f = write("ok.nqc", "task main() { }\n");
  auto r = run_rcxc({"compile", "--diagnostics=xml", f});
  EXPECT_EQ(r.exit_code, 2);
}

TEST_F(CompileCli, BinaryInputIsRejectedWithoutACrash) {
  std::string junk;
  for (int i = 0; i < 4096; ++i) junk += static_cast<char>((i * 7919) & 0xFF);
  auto f = write("junk.nqc", junk);
  auto r = run_rcxc({"compile", f});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("error:"), std::string::npos);
}

// 30 undeclared names: 20 errors are printed by default, then one note for
// the other 10; --max-errors changes the count and 0 prints all 30.
TEST_F(CompileCli, ErrorsStopAtTheLimit) {
  std::string text = "task main() {\n";
  for (int i = 1; i <= 30; ++i) text += "  x" + std::to_string(i) + " = 1;\n";
  auto file = write("many.nqc", text + "}\n");
  auto count = [](const std::string& err) {
    std::size_t n = 0;
    for (const auto& l : lines(err)) n += l.find(": error: ") != std::string::npos;
    return n;
  };
  auto r = run_rcxc({"compile", file});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count(r.err), 20u) << r.err;
  EXPECT_NE(r.err.find("'x20' is not declared"), std::string::npos);
  EXPECT_EQ(r.err.find("'x21' is not declared"), std::string::npos);
  EXPECT_NE(r.err.find("rcxc: note: 10 more errors not shown"), std::string::npos) << r.err;
  EXPECT_EQ(count(run_rcxc({"compile", file, "--max-errors", "3"}).err), 3u);
  auto all = run_rcxc({"compile", file, "--max-errors", "0"});
  EXPECT_EQ(count(all.err), 30u);
  EXPECT_EQ(all.err.find("not shown"), std::string::npos);
  EXPECT_EQ(run_rcxc({"compile", file, "--max-errors", "-1"}).exit_code, 2);
}
