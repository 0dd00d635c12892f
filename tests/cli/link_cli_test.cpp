// `rcxc brick`, `rcxc download` and `rcxc remote` end to end: the real
// binary serving a pty, other invocations (and nqc, when installed) talking to it.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "rcx/image.h"
#include "link/transport.h"
#include "tests/support/process.h"

namespace {

using rcxc::test::run_process;
using rcxc::test::run_rcxc;

// `rcxc brick --pty --fast ...` running in the background.
struct BrickProcess : rcxc::test::PtyServer {
  explicit BrickProcess(const std::vector<std::string>& extra = {}) : PtyServer({"brick", "--pty", "--fast"}, extra) {}
};

std::string write_temp(const rcxc::test::TempDir& dir, const std::string& name, const std::vector<std::uint8_t>& bytes) {
  return dir.write(name, bytes);
}

// task 0: var 0 = 7; var 0 *= 6 (the bytes nqc emits for `x = 7; x = x * 6;`).
std::string sample_rcx(const rcxc::test::TempDir& dir) {
  rcx::Image image;
  image.fragments.push_back({rcx::FragmentType::Task, 0, {0x14, 0x00, 0x02, 0x07, 0x00, 0x54, 0x00, 0x02, 0x06, 0x00}});
  image.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  return write_temp(dir, "prog.rcx", rcx::write_image(image));
}

std::string get_var0(const std::string& port) {
  for (int i = 0; i < 100; ++i) {
    auto r = run_rcxc({"remote", "--port", port, "get", "var", "0"});
    if (r.exit_code != 0) return "error: " + r.err;
    if (r.out == "42\n") return r.out;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return "never 42";
}

TEST(LinkCli, BrickPrintsItsPtyAndStopsOnInterrupt) {
  BrickProcess brick;
  ASSERT_EQ(brick.path.rfind("/dev/", 0), 0u) << brick.path;
  EXPECT_TRUE(std::filesystem::exists(brick.path));
  auto r = run_rcxc({"remote", "--port", brick.path, "versions"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "ROM 3.1, firmware 3.9\n");
  EXPECT_EQ(brick.stop(), 0);
}

// The counts said at exit: each session's opening Alive was one of the
// "retransmissions" (2 here), where none was sent twice.
TEST(LinkCli, TheBrickCountsNoRetransmissionWhereNoneWasSent) {
  rcxc::test::TempDir dir;
  std::string log = dir.path + "/brick.err";
  {
    rcxc::test::PtyServer brick({"brick", "--pty", "--fast"}, {}, log);
    ASSERT_FALSE(brick.path.empty());
    for (const char* action : {"alive", "alive", "versions"})
      ASSERT_EQ(run_rcxc({"remote", "--port", brick.path, action}).exit_code, 0) << action;
    EXPECT_EQ(brick.stop(), 0);
  }
  std::ifstream in(log);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("rcxc brick: 4 requests, 4 replies, 0 retransmissions, 0 rejected"), std::string::npos)
      << text;
}

TEST(LinkCli, DownloadRunThenReadTheVariable) {
  rcxc::test::TempDir dir;
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  auto r = run_rcxc({"download", "--port", brick.path, sample_rcx(dir), "--run"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("downloaded 10 bytes to program 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(1 block, 0 retransmissions), running"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err.find('\r'), std::string::npos);  // no progress bar when stderr is not a terminal
  EXPECT_EQ(get_var0(brick.path), "42\n");
}

TEST(LinkCli, RcxPortEnvironmentSelectsThePort) {
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  auto r = run_process({"/usr/bin/env", "RCX_PORT=" + brick.path, RCXC_BINARY, "remote", "alive"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "the RCX is alive\n");
}

TEST(LinkCli, NqcDownloadsAndRunsOnTheVirtualBrick) {
  rcxc::test::TempDir dir;
  if (::access("/usr/bin/nqc", X_OK) != 0) GTEST_SKIP() << "nqc is not installed";
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  std::string src = write_temp(dir, "prog.nqc", {});
  std::ofstream(src) << "int x;\ntask main() {\n  x = 7;\n  x = x * 6;\n}\n";
  auto d = run_process({"/usr/bin/nqc", "-S" + brick.path, "-d", src});
  ASSERT_EQ(d.exit_code, 0) << d.out << d.err;
  auto run = run_process({"/usr/bin/nqc", "-S" + brick.path, "-run"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(get_var0(brick.path), "42\n");
}

// rcxc's nqc mode speaks to the brick as nqc does: options, then the file
// and actions in the order given.
TEST(LinkCli, NqcModeDownloadsSelectsAndRuns) {
  rcxc::test::TempDir dir;
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  std::string src = write_temp(dir, "prog.nqc", {});
  std::ofstream(src) << "int x;\ntask main() {\n  x = 7;\n  x = x * 6;\n}\n";
  auto d = run_rcxc({"nqc", "-S" + brick.path, "-d", "-pgm", "3", src, "-run"});
  ASSERT_EQ(d.exit_code, 0) << d.out << d.err;
  EXPECT_NE(d.err.find("to program 3"), std::string::npos) << d.err;
  EXPECT_EQ(get_var0(brick.path), "42\n");
  auto log = run_rcxc({"nqc", "-S" + brick.path, "-datalog", "-near", "-far", "-sleep", "5", "-msg", "3", "-clear"});
  EXPECT_EQ(log.exit_code, 0) << log.err;
  EXPECT_NE(log.out.find("0 entries"), std::string::npos) << log.out;
}

// The datalog goes to the -R file; a file that takes nothing (a full disk:
// /dev/full) is a failure with the text on stderr, not exit 0 with it lost.
TEST(LinkCli, NqcModeDatalogToAFileThatCannotTakeItFails) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  rcxc::test::TempDir dir;
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  auto ok = run_rcxc({"nqc", "-S" + brick.path, "-R" + dir.path + "/log.txt", "-datalog"});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(rcxc::test::read_text_file(dir.path + "/log.txt"), "0 entries\n");
  auto full = run_rcxc({"nqc", "-S" + brick.path, "-R/dev/full", "-datalog"});
  EXPECT_EQ(full.exit_code, 243) << full.err;
  EXPECT_NE(full.err.find("0 entries\nrcxc (as nqc): cannot write the output file /dev/full (-R)"), std::string::npos)
      << full.err;
}

TEST(LinkCli, NqcModeWithoutATowerExitsAsNqc) {
  auto r = run_rcxc({"nqc", "-S/dev/no-such-tower", "-run"});
  EXPECT_EQ(r.exit_code, 255);
  EXPECT_NE(r.err.find("no-such-tower"), std::string::npos) << r.err;
}

TEST(LinkCli, DownloadCompilesNqcSource) {
  rcxc::test::TempDir dir;
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  std::string src = write_temp(dir, "prog.nqc", {});
  std::ofstream(src) << "int x;\ntask main() {\n  x = 7;\n  x = x * 6;\n}\n";
  auto r = run_rcxc({"download", "--port", brick.path, src, "--run"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(get_var0(brick.path), "42\n");
}

TEST(LinkCli, DownloadTakesTheCompilerOptionsAndAnUpperCaseName) {
  rcxc::test::TempDir dir;
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  std::string src = write_temp(dir, "PROG.NQC", {});
  std::ofstream(src) << "int x;\ntask main() {\n  x = VALUE;\n}\n";
  auto r = run_rcxc({"download", "--port", brick.path, "-DVALUE=42", "-O0", src, "--run"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(get_var0(brick.path), "42\n");
}

TEST(LinkCli, CompileErrorsAreExit1BeforeTouchingThePort) {
  rcxc::test::TempDir dir;
  std::string src = write_temp(dir, "bad.nqc", {});
  std::ofstream(src) << "task main() { y = 1; }\n";
  auto r = run_rcxc({"download", "--port", "/dev/no-such-tower", src});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.nqc:1:"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("no-such-tower"), std::string::npos) << r.err;
}

TEST(LinkCli, MissingPortIsExit3) {
  rcxc::test::TempDir dir;
  auto d = run_rcxc({"download", "--port", "/dev/no-such-tower", sample_rcx(dir)});
  EXPECT_EQ(d.exit_code, 3) << d.err;
  EXPECT_NE(d.err.find("does not exist"), std::string::npos) << d.err;
  auto r = run_rcxc({"remote", "--port", "/dev/no-such-tower", "alive"});
  EXPECT_EQ(r.exit_code, 3);
  // A device that is no tower is a port that cannot be used, not a silent
  // RCX ("USB tower /dev/null was closed", exit 4).
  auto null = run_rcxc({"remote", "--port", "/dev/null", "alive"});
  EXPECT_EQ(null.exit_code, 3) << null.err;
  EXPECT_NE(null.err.find("rcxc remote: /dev/null is not a tower"), std::string::npos) << null.err;
}

TEST(LinkCli, SilentBrickIsExit4) {
  rcxc::test::TempDir dir;
  auto pty = rcx::open_pty();  // nobody answers on it
  ASSERT_TRUE(std::holds_alternative<rcx::Pty>(pty));
  auto& p = std::get<rcx::Pty>(pty);
  auto d = run_rcxc({"download", "--port", p.slave_path, "--retries", "1", sample_rcx(dir)});
  EXPECT_EQ(d.exit_code, 4) << d.err;
  auto r = run_rcxc({"remote", "--port", p.slave_path, "--retries", "0", "battery"});
  EXPECT_EQ(r.exit_code, 4) << r.err;
  rcx::close_pty(p);
}

TEST(LinkCli, BadInvocationsAreUsageErrors) {
  EXPECT_EQ(run_rcxc({"brick"}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"brick", "--pty", "--noise", "2"}).exit_code, 2);
  // "nan" passed the range check and the brick served (found while writing
  // the command-line property test); the time limit stops a regression here.
  auto nan = run_rcxc({"brick", "--pty", "--noise", "nan"}, "", 10'000);
  EXPECT_EQ(nan.exit_code, 2) << nan.err;
  EXPECT_NE(nan.err.find("--noise: 'nan' is not a number (0..1)"), std::string::npos) << nan.err;
  EXPECT_EQ(run_rcxc({"brick", "--pty", "--noise", ""}, "", 10'000).exit_code, 2);  // not 0
  EXPECT_EQ(run_rcxc({"download"}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"download", "x.rcx", "--program", "9"}).exit_code, 2);
  BrickProcess brick;
  ASSERT_FALSE(brick.path.empty());
  auto r = run_rcxc({"remote", "--port", brick.path, "fly"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown action"), std::string::npos) << r.err;
}

TEST(LinkCli, ABadActionIsExit2EvenWithoutATower) {
  // Wrong words are a command-line error (2) before any port is opened,
  // not "no tower" (3) which would send the user looking for a cable.
  for (std::vector<std::string> words : {std::vector<std::string>{"fly"}, {"run", "9"}, {"get"}, {"get", "var", "99"},
                                         {"get", "timer", "4"}, {"message", "300"}}) {
    std::vector<std::string> args{"remote", "--port", "/dev/no-such-tower"};
    args.insert(args.end(), words.begin(), words.end());
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << words[0] << ": " << r.err;
    EXPECT_EQ(r.err.find("does not exist"), std::string::npos) << r.err;
  }
  auto missing = run_rcxc({"remote", "--port", "/dev/no-such-tower", "firmware", "/no/such/firmware.srec"});
  EXPECT_EQ(missing.exit_code, 1) << missing.err;
  EXPECT_NE(missing.err.find("cannot read /no/such/firmware.srec: no such file"), std::string::npos) << missing.err;
  auto dir = run_rcxc({"remote", "--port", "/dev/no-such-tower", "firmware", std::filesystem::temp_directory_path().string()});
  EXPECT_EQ(dir.exit_code, 1) << dir.err;
  EXPECT_NE(dir.err.find("is a directory, not a firmware file"), std::string::npos) << dir.err;
  // A correct action still needs the tower.
  EXPECT_EQ(run_rcxc({"remote", "--port", "/dev/no-such-tower", "get", "var", "31"}).exit_code, 3);
}

// `rcxc remote alve` listed the actions without a word on which was meant,
// where rcxc's other commands (and `rcxc nxt`) give a did-you-mean.
TEST(LinkCli, AMisspeltRemoteActionGetsADidYouMean) {
  auto near = run_rcxc({"remote", "--port", "/dev/no-such-tower", "alve"});
  EXPECT_EQ(near.exit_code, 2) << near.err;
  EXPECT_EQ(near.err.rfind("rcxc remote: unknown action 'alve': did you mean 'alive'?\nactions:\n", 0), 0u) << near.err;
  EXPECT_NE(near.err.find("  raw HEX...            send one request and print the reply\n"), std::string::npos);
  auto far = run_rcxc({"remote", "--port", "/dev/no-such-tower", "zzzzzz", "1"});
  EXPECT_EQ(far.exit_code, 2) << far.err;
  EXPECT_EQ(far.err.rfind("rcxc remote: unknown action 'zzzzzz': the actions are listed below\n", 0), 0u) << far.err;
  // A known action with wrong arguments keeps its own message.
  auto known = run_rcxc({"remote", "--port", "/dev/no-such-tower", "watch"});
  EXPECT_EQ(known.err, "rcxc remote: usage: watch HH:MM|now\n");
}

TEST(LinkCli, BadImageIsExit1) {
  rcxc::test::TempDir dir;
  std::string path = write_temp(dir, "bad.rcx", {'R', 'C', 'X', 'I', 0x09});
  auto r = run_rcxc({"download", "--port", "/dev/null", path});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.rcx"), std::string::npos) << r.err;
}

// Found by the command-line property test: the image was read with its own
// loop, which threw on a directory and aborted (exit 134).
TEST(LinkCli, DownloadingADirectoryIsExit1) {
  rcxc::test::TempDir d;
  auto r = run_rcxc({"download", "--port", "/dev/no-such-tower", d.path});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(d.path + ": is a directory, not a source file or an .rcx image"), std::string::npos) << r.err;
}

}  // namespace

// `rcxc remote --csv alive` (or get, battery, ...) took --csv and ignored
// it; it shapes the datalog alone. Refused before the port is opened.
TEST(LinkCli, CsvWithAnActionButDatalogIsAUsageError) {
  auto r = run_rcxc({"remote", "--port", "/dev/no-such-tower", "--csv", "alive"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--csv is for datalog, not alive"), std::string::npos) << r.err;
  auto datalog = run_rcxc({"remote", "--port", "/dev/no-such-tower", "--csv", "datalog"});
  EXPECT_EQ(datalog.exit_code, 3) << datalog.err;
}
