// `rcxc test` end to end: pass/fail lines, failure messages, exit codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <sys/stat.h>
#include <unistd.h>

#include "tests/support/process.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {


constexpr const char* kCounter =
    "int n;\n"
    "task main() { repeat (3) { n += 2; PlaySound(SOUND_CLICK); } }\n";

}  // namespace

TEST(TestCommand, PassingTestExitsZero) {
  TempDir d;
  auto f = d.write("ok.nqc", std::string("// @expect global n == 6\n// @expect count sound 0 == 3\n") + kCounter);
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("PASS " + f), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 passed, 0 failed"), std::string::npos) << r.out;
}

TEST(TestCommand, FailingTestShowsExpectedAndActual) {
  TempDir d;
  auto f = d.write("bad.nqc", std::string("// @expect global n == 7\n") + kCounter);
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("FAIL " + f), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(f + ":1: error: expected global n == 7; got n = 6"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0 passed, 1 failed"), std::string::npos) << r.out;
}

TEST(TestCommand, FolderRunsEveryFileAndCountsBoth) {
  TempDir d;
  d.write("a.nqc", std::string("// @expect global n == 6\n") + kCounter);
  d.write("b.nqc", std::string("// @expect global n == 5\n") + kCounter);
  d.write("notes.txt", "not a test");
  auto r = run_rcxc({"test", d.path});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("1 passed, 1 failed"), std::string::npos) << r.out;
}

TEST(TestCommand, ExpectedCompileErrorPasses) {
  TempDir d;
  auto f = d.write("err.nqc", "// @expect-error line 2: not declared\ntask main() { zork = 1; }\n");
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST(TestCommand, UnexpectedCompileErrorFails) {
  TempDir d;
  auto f = d.write("err.nqc", "task main() { zork = 1; }\n");
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("unexpected compile error"), std::string::npos) << r.out;
}

TEST(TestCommand, BadDirectiveIsReportedWithItsLine) {
  TempDir d;
  auto f = d.write("dir.nqc", std::string("\n// @expect global n ~ 6\n") + kCounter);
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(f + ":2: error: bad directive"), std::string::npos) << r.out;
}

TEST(TestCommand, MissingPathIsAnError) {
  auto r = run_rcxc({"test", "/no/such/file.nqc"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no such file or folder"), std::string::npos) << r.err;
}

// A device exists but holds no test: it used to be called missing.
TEST(TestCommand, ADeviceIsNeitherAFileNorAFolder) {
  auto r = run_rcxc({"test", "/dev/zero"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/dev/zero: not a file or a folder"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("no such file"), std::string::npos) << r.err;
}

// Inside a folder too: a pipe or a device named .nqc was passed over
// without a word ("1 passed, 0 failed", exit 0), where one named on the
// command line is refused. The search goes on, and it is said.
TEST(TestCommand, APipeOrDeviceInAFolderIsSaidNotSkipped) {
  TempDir d;
  d.write("good.nqc", std::string("// @expect global n == 6\n") + kCounter);
  ASSERT_EQ(::mkfifo((d.path + "/pipe.nqc").c_str(), 0600), 0);
  std::filesystem::create_symlink("/dev/zero", d.path + "/zero.nqc");
  auto r = run_rcxc({"test", d.path}, "", 30'000);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find(d.path + "/pipe.nqc: not a file (a device, a pipe or a socket)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(d.path + "/zero.nqc: not a file (a device, a pipe or a socket)"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("PASS " + d.path + "/good.nqc"), std::string::npos) << r.out;
}

TEST(TestCommand, InputsDriveTheProgram) {
  TempDir d;
  auto f = d.write("touch.nqc",
                   "// @input at 300ms: sensor 1 pressed\n"
                   "// @expect event at 300ms: output A on fwd\n"
                   "// @expect stop ended\n"
                   "task main() { SetSensor(SENSOR_1, SENSOR_TOUCH); until (SENSOR_1 == 1); On(OUT_A); }\n");
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST(TestCommand, NqcFlagTakesNoValueSoEveryPathIsATest) {
  if (rcxc::test::run_process({"/bin/sh", "-c", "command -v nqc"}).exit_code != 0) GTEST_SKIP() << "nqc not installed";
  TempDir d;
  auto a = d.write("a.nqc", std::string("// @expect global n == 6\n") + kCounter);
  auto b = d.write("b.nqc", std::string("// @expect global n == 6\n") + kCounter);
  auto r = run_rcxc({"test", "--nqc", a, b});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("2 passed, 0 failed"), std::string::npos) << r.out;
}

TEST(TestCommand, ScenarioFileBesideTheTestFeedsInputs) {
  TempDir d;
  d.write("press.toml", "[[input]]\nat_ms = 300\nsensor = 1\nraw = 100\n");
  auto f = d.write("s.nqc",
                   "// @scenario press.toml\n"
                   "// @expect event at 300ms: output A on fwd\n"
                   "task main() { SetSensor(SENSOR_1, SENSOR_TOUCH); until (SENSOR_1 == 1); On(OUT_A); }\n");
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST(TestCommand, BrokenScenarioFileFailsWithItsLine) {
  TempDir d;
  d.write("bad.toml", "[[input]]\nat_ms = 300\nsensor = 9\nraw = 100\n");
  auto f = d.write("s.nqc", std::string("// @scenario bad.toml\n") + kCounter);
  auto r = run_rcxc({"test", f});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("bad.toml:"), std::string::npos) << r.out;
}

// Tests run in parallel but report in file order: a slow first test (an
// hour of brick time busy, about two million instructions) and many quick
// ones give the same output with one job and with eight.
TEST(TestCommand, ParallelRunsKeepTheOutputOrder) {
  TempDir d;
  d.write("a_slow.nqc", "// @for 3600s\n// @expect global n == 5\n"
                        "int n;\ntask main() { while (true) { n = 5; } }\n");
  for (int i = 0; i < 12; ++i)
    d.write("b" + std::to_string(10 + i) + ".nqc",
            "// @expect global n == " + std::to_string(i % 3 == 0 ? 7 : 6) + "\n" + kCounter);
  auto one = run_rcxc({"test", "-j", "1", d.path});
  auto many = run_rcxc({"test", "-j", "8", d.path});
  EXPECT_EQ(one.exit_code, 1);
  EXPECT_EQ(many.exit_code, 1);
  EXPECT_EQ(one.out, many.out);
  EXPECT_LT(one.out.find("a_slow.nqc"), one.out.find("b10.nqc")) << one.out;
  EXPECT_NE(many.out.find("9 passed, 4 failed"), std::string::npos) << many.out;
  auto bad = run_rcxc({"test", "-j", "0", d.path});
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
}

TEST(TestCommand, LinkLoopsAreReportedAndTheSearchGoesOn) {
  // A file link to itself made the search throw (ELOOP) and rcxc abort; a
  // folder link back up is not followed, so the good test runs once.
  TempDir d;
  std::filesystem::create_directory(d.path + "/sub");
  d.write("sub/good.nqc", std::string("// @expect global n == 6\n") + kCounter);
  std::filesystem::create_symlink(d.path + "/sub/self.nqc", d.path + "/sub/self.nqc");
  std::filesystem::create_directory_symlink(d.path, d.path + "/sub/up");
  auto r = run_rcxc({"test", d.path}, "", 30'000);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("rcxc test: cannot read " + d.path +
                       "/sub/self.nqc: a loop of symbolic links that never reaches a file"),
            std::string::npos)
      << r.err;
  // Named on the command line, the loop was "no such file or folder".
  auto named = run_rcxc({"test", d.path + "/sub/self.nqc"}, "", 30'000);
  EXPECT_EQ(named.exit_code, 1) << named.err;
  EXPECT_NE(named.err.find("rcxc test: cannot read " + d.path +
                           "/sub/self.nqc: a loop of symbolic links that never reaches a file"),
            std::string::npos)
      << named.err;
  EXPECT_NE(r.out.find("PASS " + d.path + "/sub/good.nqc"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 passed, 0 failed"), std::string::npos) << r.out;
}

// A sub-folder that cannot be read is reported by name and the search goes
// on: the readable test still runs and passes, and the exit code says that
// not everything was checked. Root reads every folder whatever its mode, so
// as root the command runs as `nobody` (setpriv); skipped without setpriv.
TEST(TestCommand, UnreadableSubFolderIsReportedAndTheRestRuns) {
  namespace fs = std::filesystem;
  TempDir d;
  fs::permissions(d.path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
  fs::create_directory(d.path + "/good");
  std::ofstream(d.path + "/good/ok.nqc") << "// @for 100ms\n// @expect global v == 3\nint v;\ntask main() { v = 3; }\n";
  fs::create_directory(d.path + "/locked");
  std::ofstream(d.path + "/locked/hidden.nqc") << "task main() { }\n";
  fs::permissions(d.path + "/locked", fs::perms::none);
  std::vector<std::string> command{RCXC_BINARY, "test", d.path};
  if (geteuid() == 0) {
    auto setpriv = rcxc::test::run_process({"/bin/sh", "-c", "command -v setpriv"});
    if (setpriv.exit_code != 0) GTEST_SKIP() << "running as root and setpriv is missing: root reads every folder";
    command.insert(command.begin(), {setpriv.out.substr(0, setpriv.out.find('\n')), "--reuid=65534",
                                     "--regid=65534", "--clear-groups"});
    // A checkout under a folder only root may enter (/root) cannot be run
    // as nobody at all: nothing to learn about folders there.
    if (rcxc::test::run_process({command[0], command[1], command[2], command[3], RCXC_BINARY, "version"}).exit_code !=
        0) {
      fs::permissions(d.path + "/locked", fs::perms::owner_all);
      GTEST_SKIP() << "nobody cannot run " << RCXC_BINARY;
    }
  }
  auto r = rcxc::test::run_process(command);
  fs::permissions(d.path + "/locked", fs::perms::owner_all);  // so TempDir can remove it
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("rcxc test: cannot read folder " + d.path + "/locked: Permission denied"), std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("1 passed, 0 failed"), std::string::npos) << r.out;
}

// --junit: the same results as a JUnit XML report, for CI and grading; the
// printed output stays as it was, and the report never replaces a test.
TEST(TestCommand, JunitWritesTheResultsAsAReport) {
  TempDir d;
  auto ok = d.write("ok.nqc", std::string("// @expect global n == 6\n") + kCounter);
  auto bad = d.write("bad.nqc", std::string("// @expect global n == 7\n") + kCounter);
  std::string report = d.path + "/report.xml";
  auto r = run_rcxc({"test", d.path, d.path + "/missing", "--junit", report});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("1 passed, 1 failed"), std::string::npos) << r.out;
  std::string xml = rcxc::test::read_text_file(report);
  EXPECT_NE(xml.find("<testsuite name=\"rcxc test\" tests=\"3\" failures=\"1\" errors=\"1\""), std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<testcase name=\"" + ok + "\""), std::string::npos) << xml;
  EXPECT_NE(xml.find(bad + ":1: expected global n == 7; got n = 6"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<error message=\"no such file or folder: " + d.path + "/missing\"/>"), std::string::npos) << xml;

  auto over = run_rcxc({"test", ok, "--junit", ok});
  EXPECT_EQ(over.exit_code, 2) << over.err;
  EXPECT_NE(over.err.find("refusing to write the report to " + ok), std::string::npos) << over.err;
  EXPECT_EQ(rcxc::test::read_text_file(ok), std::string("// @expect global n == 6\n") + kCounter);

  auto nowhere = run_rcxc({"test", ok, "--junit", d.path + "/no/such/folder/r.xml"});
  EXPECT_EQ(nowhere.exit_code, 1);
  EXPECT_NE(nowhere.err.find("cannot write the report"), std::string::npos) << nowhere.err;
  // Said before any test runs, not after all of them.
  EXPECT_EQ(nowhere.out.find("PASS"), std::string::npos) << nowhere.out;
  auto folder = run_rcxc({"test", ok, "--junit", d.path});
  EXPECT_EQ(folder.exit_code, 1);
  EXPECT_NE(folder.err.find("cannot write the report " + d.path), std::string::npos) << folder.err;
  EXPECT_EQ(folder.out.find("PASS"), std::string::npos) << folder.out;
}

// A test's @scenario file is an input too: a report named as it replaced
// the scenario with XML once the tests had run.
TEST(TestCommand, AJunitReportOverATestsScenarioIsRefused) {
  TempDir d;
  const std::string scenario = "[[input]]\nat_ms = 5\nmessage = 3\n";
  d.write("inputs.toml", scenario);
  std::string test = d.write("t.nqc", "// @scenario inputs.toml\n// @expect message == 3\ntask main() { Wait(10); }\n");
  auto r = run_rcxc({"test", d.path, "--junit", d.path + "/inputs.toml"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("refusing to write the report to " + d.path + "/inputs.toml: it is the scenario " + d.path +
                       "/inputs.toml of " + test),
            std::string::npos)
      << r.err;
  EXPECT_EQ(rcxc::test::read_text_file(d.path + "/inputs.toml"), scenario);
  EXPECT_EQ(run_rcxc({"test", test}).exit_code, 0);
}

// --nqc-path without --nqc was taken and ignored: the tests ran on rcxc's
// code and passed, whatever nqc the user meant to try.
TEST(TestCommand, AnNqcPathWithoutNqcIsAUsageError) {
  TempDir d;
  std::string test = d.write("t.nqc", "// @expect stop ended\ntask main() {}\n");
  auto r = run_rcxc({"test", "--nqc-path", "/no/such/nqc", test});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--nqc-path requires --nqc"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("PASS"), std::string::npos) << r.out;
}

// README said '-' reads the program from the standard input for "any command
// but compare"; `rcxc test -` answered "no such file or folder: -".
TEST(TestCommand, TheStandardInputIsRefusedWithItsReason) {
  auto r = run_rcxc({"test", "-"}, "// @expect stop ended\ntask main() {}\n");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("rcxc test reads test files, not the standard input"), std::string::npos) << r.err;
}

// A binary file found among the tests was "an .rcx image, not an NQC test
// program": it is binary data, and an image is still called an image.
TEST(TestCommand, ABinaryFileIsNotCalledAnImage) {
  TempDir d;
  std::string binary = d.write("junk.nqc", std::string("\x01\x00\xff\x02", 4));
  auto r = run_rcxc({"test", binary});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("junk.nqc: error: binary data, not an NQC test program"), std::string::npos) << r.out;
}

// `@brick FILE` runs another program on a second brick in the room: the
// test sees its messages. A brick that cannot run fails the test at the
// @brick line, saying why.
TEST(TestCommand, AnotherBrickInTheRoomTalksToTheTest) {
  TempDir d;
  d.write("echo.nqc", "task main() { ClearMessage(); until (Message() != 0); SendMessage(Message() + 1); }\n");
  std::string test = d.write("t.nqc",
                             "// @brick echo.nqc\n// @for 1s\n// @expect event: receive 8\n"
                             "task main() { SendMessage(7); Wait(50); }\n");
  auto r = run_rcxc({"test", test});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  // Without the other brick nothing answers.
  std::string alone = d.write("alone.nqc", "// @for 1s\n// @expect event: receive 8\ntask main() { SendMessage(7); Wait(50); }\n");
  EXPECT_EQ(run_rcxc({"test", alone}).exit_code, 1);
  std::string missing = d.write("m.nqc", "// @for 1s\n// @brick nowhere.nqc\ntask main() { }\n");
  auto m = run_rcxc({"test", missing});
  EXPECT_EQ(m.exit_code, 1);
  EXPECT_NE(m.out.find("m.nqc:2: error: @brick nowhere.nqc: cannot read "), std::string::npos) << m.out;
  d.write("broken.nqc", "task main() { Wiat(1); }\n");
  std::string broken = d.write("b.nqc", "// @brick broken.nqc\ntask main() { }\n");
  auto b = run_rcxc({"test", broken});
  EXPECT_EQ(b.exit_code, 1);
  EXPECT_NE(b.out.find("b.nqc:1: error: @brick broken.nqc: does not compile: line 1: 'Wiat' is not declared"),
            std::string::npos)
      << b.out;
}

// The other brick's program breaks down: the test says so at its @brick
// line. It said only "no matching event" here, or passed without a word.
TEST(TestCommand, AFaultInAnotherBrickFailsTheTestAtItsBrickLine) {
  TempDir d;
  d.write("bad.nqc", "task main() { asm { 0x01 }; SendMessage(1); }\n");
  std::string quiet = d.write("q.nqc", "// @for 1s\n// @brick bad.nqc\n// @expect count send == 0\ntask main() { }\n");
  auto r = run_rcxc({"test", quiet});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("q.nqc:2: error: @brick bad.nqc: its program faulted at "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" ms: not a program opcode"), std::string::npos) << r.out;
}

// A folder or a device named by @brick is called what it is, as `rcxc run`
// calls it, not "it could not be read".
TEST(TestCommand, ABrickThatIsAFolderIsCalledAFolder) {
  TempDir d;
  std::filesystem::create_directory(d.path + "/sub.nqc");
  std::string test = d.write("f.nqc", "// @brick sub.nqc\ntask main() { }\n");
  auto r = run_rcxc({"test", test});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("f.nqc:1: error: @brick sub.nqc: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sub.nqc: is a directory, not a source file"), std::string::npos) << r.out;
  std::string device = d.write("z.nqc", "// @brick /dev/zero\ntask main() { }\n");
  auto z = run_rcxc({"test", device});
  EXPECT_EQ(z.exit_code, 1) << z.out;
  EXPECT_NE(z.out.find("/dev/zero: not a file (a device, a pipe or a socket)"), std::string::npos) << z.out;
}
