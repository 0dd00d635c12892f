// The commands that compile (run, test, compare, disasm; download in
// link_cli_test) take `rcxc compile`'s options, and tell source from an
// image by content, or by the name in any case.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "nlohmann/json.hpp"
#include "rcx/image.h"
#include "tests/support/process.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

// Sets a global from a macro defined on the command line, in a header
// included from another folder.
constexpr const char* kUsesHeader = "#include \"speed.nqh\"\nint v;\ntask main() { v = SPEED * FACTOR; }\n";

int global_after_run(const std::vector<std::string>& args) {
  auto r = run_rcxc(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return -1;
  return nlohmann::json::parse(r.out)["globals"]["v"].get<int>();
}

}  // namespace

TEST(CompilerOptions, RunTakesIncludeDefineAndLevel) {
  TempDir d;
  std::filesystem::create_directory(d.path + "/inc");
  d.write("inc/speed.nqh", "#define SPEED 3\n");
  auto src = d.write("p.nqc", kUsesHeader);
  EXPECT_EQ(global_after_run({"run", "-I", d.path + "/inc", "-DFACTOR=5", "-O0", src, "--report", "json"}), 15);
  EXPECT_EQ(global_after_run({"run", "-I" + d.path + "/inc", "-DFACTOR=2", "-O1", src, "--report", "json"}), 6);
  // Without -I the header is not found: the compiler says so.
  auto r = run_rcxc({"run", "-DFACTOR=2", src});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("speed.nqh"), std::string::npos) << r.err;
}

TEST(CompilerOptions, BadMacroNamesAndLevelsAreUsageErrors) {
  TempDir d;
  auto src = d.write("p.nqc", "task main() {}\n");
  for (const std::string command : {"run", "test", "compare", "disasm", "download"}) {
    auto r = run_rcxc({command, "-D1X", src});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("a macro name must be an identifier"), std::string::npos) << command << ": " << r.err;
    r = run_rcxc({command, "-O3", src});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
  }
}

// -D task=1 replaced the keyword (every task then failed to parse) and
// -D acquire was taken; as a #define of them is refused, so is the option.
TEST(CompilerOptions, AKeywordAsAMacroNameIsAUsageError) {
  TempDir d;
  auto src = d.write("p.nqc", "task main() {}\n");
  for (const std::string command : {"compile", "run", "disasm"}) {
    auto r = run_rcxc({command, "-Dtask=1", src});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("-Dtask=1: 'task' cannot be a macro name: it is a keyword"), std::string::npos) << r.err;
    r = run_rcxc({command, "-Uacquire", src});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("-Uacquire: 'acquire' cannot be a macro name: it is reserved by nqc (a statement of the RCX 2 firmware)"),
              std::string::npos)
        << r.err;
  }
  EXPECT_EQ(run_rcxc({"compile", "-Duntil=1", "-Dinline", src, "-o", d.path + "/p.rcx"}).exit_code, 0);
}

// gcc's -O3 was read as nqc's -O<file>: "the output file is -o 3". A level
// that does not exist is named so; a file name still gets nqc's hint.
TEST(CompilerOptions, ALevelThatDoesNotExistIsNotTakenForAnOutputFile) {
  TempDir d;
  auto src = d.write("p.nqc", "task main() {}\n");
  for (const std::string level : {"-O3", "-Ofast"}) {
    auto r = run_rcxc({"compile", level, src});
    EXPECT_EQ(r.exit_code, 2) << level << ": " << r.err;
    EXPECT_NE(r.err.find(level + ": there is no such optimisation level"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("-o " + level.substr(2)), std::string::npos) << r.err;
  }
  auto file = run_rcxc({"compile", "-Oout.rcx", src});
  EXPECT_NE(file.err.find("the output file is -o out.rcx"), std::string::npos) << file.err;
}

TEST(CompilerOptions, SourceIsKnownByContentOrByItsNameInAnyCase) {
  TempDir d;
  const std::string program = "int v;\ntask main() { v = 4; }\n";
  for (const std::string name : {"UP.NQC", "mixed.Nqc", "prog.txt", "no_extension"}) {
    auto src = d.write(name, program);
    EXPECT_EQ(global_after_run({"run", src, "--report", "json"}), 4) << name;
    auto r = run_rcxc({"disasm", src});
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_NE(r.out.find("task 0 main"), std::string::npos) << name << ": " << r.out;
  }
}

TEST(CompilerOptions, AnImageIsKnownByItsSignatureWhateverItsName) {
  TempDir d;
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x14, 0x00, 0x02, 0x09, 0x00}});  // var[0] = 9
  img.symbols.push_back({rcx::SymbolType::Variable, 0, "v"});
  auto path = d.write("looks_like_source.nqc", rcx::write_image(img));
  EXPECT_EQ(global_after_run({"run", path, "--report", "json"}), 9);
  auto r = run_rcxc({"disasm", path});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("set var[0], 9"), std::string::npos) << r.out;
  r = run_rcxc({"test", path});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("an .rcx image, not an NQC test program"), std::string::npos) << r.out;
  // A name ending in .RCX (any case) that is no image is refused as one.
  auto fake = d.write("FAKE.RCX", std::string("task main() {}\n"));
  r = run_rcxc({"run", fake});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("not an RCX image"), std::string::npos) << r.err;
}

TEST(CompilerOptions, TestFindsUpperCaseNqcFilesInFolders) {
  TempDir d;
  d.write("A.NQC", "int v;\n// @expect global v == 1\ntask main() { v = 1; }\n");
  d.write("b.Nqc", "int v;\n// @expect global v == 2\ntask main() { v = 2; }\n");
  d.write("notes.txt", "not a test\n");
  auto r = run_rcxc({"test", d.path});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("2 passed, 0 failed"), std::string::npos) << r.out;
}

TEST(CompilerOptions, TestTakesOptionsFromTheCommandLineAndFromTheFile) {
  TempDir d;
  std::filesystem::create_directory(d.path + "/inc");
  d.write("inc/speed.nqh", "#define SPEED 3\n");
  // @options: -I relative to the test's folder, a -D; the command line's
  // -D comes first, the file's after it (so the file's value wins).
  auto f = d.write("t.nqc", std::string("// @options -I inc -DFACTOR=7\n// @expect global v == 21\n") + kUsesHeader);
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  auto g = d.write("u.nqc", std::string("// @options -I inc\n// @expect global v == 12\n") + kUsesHeader);
  r = run_rcxc({"test", "-DFACTOR=4", g});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  r = run_rcxc({"test", g});  // FACTOR undefined: does not compile
  EXPECT_EQ(r.exit_code, 1) << r.out;
}

TEST(CompilerOptions, ATestPicksItsLevel) {
  TempDir d;
  // The level shows in slot 1: -O0 keeps the local i there, -O1 and -Os
  // fold it away. The file's level wins over the command line's.
  const std::string program = "int v;\ntask main() { int i; i = 2; v = i * 3; }\n";
  for (auto [level, slot1] : {std::pair{"-O0", 2}, {"-O1", 0}, {"-O2", 0}, {"-Os", 0}}) {
    auto f = d.write(std::string("t") + level + ".nqc", std::string("// @options ") + level +
                                                            "\n// @expect global v == 6\n// @expect var 1 == " +
                                                            std::to_string(slot1) + "\n" + program);
    auto r = run_rcxc({"test", f});
    EXPECT_EQ(r.exit_code, 0) << level << "\n" << r.out << r.err;
    r = run_rcxc({"test", std::string(level) == "-O0" ? "-Os" : "-O0", f});
    EXPECT_EQ(r.exit_code, 0) << level << "\n" << r.out << r.err;
  }
  auto bad = d.write("bad.nqc", "// @options -O3\n// @expect global v == 0\nint v;\ntask main() {}\n");
  auto r = run_rcxc({"test", bad});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(bad + ":1: error: bad @options"), std::string::npos) << r.out;
  auto twice = d.write("twice.nqc", "// @options -O0\n// @options -O1\nint v;\ntask main() {}\n");
  r = run_rcxc({"test", twice});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("a second @options"), std::string::npos) << r.out;
}

TEST(CompilerOptions, TaskExpectationsHoldAtOs) {
  // At -Os main would run `worker` in its own place (a tail start) and no
  // task-start of worker would happen; rcxc test keeps worker a task.
  TempDir d;
  auto f = d.write("t.nqc",
                   "// @expect event: task-start worker\n// @expect count task-start worker == 1\n"
                   "// @expect global v == 3\nint v;\ntask worker() { v = 3; }\ntask main() { start worker; }\n");
  for (const std::string level : {"-O0", "-O1", "-Os"}) {
    auto r = run_rcxc({"test", level, f});
    EXPECT_EQ(r.exit_code, 0) << level << "\n" << r.out << r.err;
  }
  // rcxc run keeps the pass: worker's code runs in main.
  auto r = run_rcxc({"run", f, "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("\"worker\""), std::string::npos) << r.out;
}

TEST(CompilerOptions, CompareGivesNqcTheSameMacros) {
  if (::access("/usr/bin/nqc", X_OK) != 0) GTEST_SKIP() << "nqc is not installed";
  TempDir d;
  std::filesystem::create_directory(d.path + "/inc");
  d.write("inc/speed.nqh", "#define SPEED 3\n");
  auto src = d.write("p.nqc", std::string(kUsesHeader) + "task other() {}\n");
  auto r = run_rcxc({"compare", "-I", d.path + "/inc", "-DFACTOR=2", src});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("same"), std::string::npos) << r.out;
}

TEST(CompilerOptions, AMissingSourceIsCannotOpenNotACompileError) {
  TempDir d;
  for (const std::string command : {"run", "disasm", "download"}) {
    auto r = run_rcxc({command, d.path + "/missing.NQC", "--port", "/dev/null"});
    if (command != "download") r = run_rcxc({command, d.path + "/missing.NQC"});
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
    EXPECT_NE(r.err.find("missing.NQC: cannot open file"), std::string::npos) << command << ": " << r.err;
    EXPECT_EQ(r.err.find("does not compile"), std::string::npos) << command << ": " << r.err;
  }
}
