// Every command that reads a program from a path refuses a device, a pipe
// or a socket by name: `rcxc run /dev/null` used to read it as an image
// "too short", `rcxc compile /dev/null` as a program without task main.
// `rcxc remote firmware /dev/null` said "no data records". The standard
// input, '-', stays accepted where a command takes it.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>
#include <vector>

#include "tests/support/process.h"

namespace {

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

constexpr const char* kProgram = "task main()\n{\n  PlaySound(SOUND_CLICK);\n}\n";

// `rcxc ARGS` with FILE in place of "FILE": refused with exit 1, naming the
// path as no file.
void expect_refused(std::vector<std::string> args, const std::string& file) {
  for (auto& a : args)
    if (a == "FILE") a = file;
  // A reader that opened the pipe would wait for a writer: the time limit
  // turns that into a failure instead of a hang.
  auto r = run_rcxc(args, "", 10'000);
  std::string shown = args[0] + " " + file;
  EXPECT_FALSE(r.timed_out) << shown;
  EXPECT_EQ(r.exit_code, 1) << shown << "\n" << r.err;
  EXPECT_NE(r.err.find("rcxc " + args[0] + ": " + file + ": not a file (a device, a pipe or a socket); "),
            std::string::npos)
      << shown << "\n" << r.err;
  EXPECT_EQ(r.err.find("too short"), std::string::npos) << shown << "\n" << r.err;
  EXPECT_EQ(r.err.find("task main"), std::string::npos) << shown << "\n" << r.err;
}

const std::vector<std::vector<std::string>> kCommands = {
    {"compile", "FILE", "-o", "/dev/null"},
    {"compile", "-E", "FILE"},
    {"run", "FILE"},
    {"disasm", "FILE"},
    {"compare", "FILE"},
    {"download", "--port", "/dev/no-such-tower", "FILE"},
    {"format", "FILE"},
    {"format", "-i", "FILE"},
    {"remote", "--port", "/dev/no-such-tower", "firmware", "FILE"},
};

TEST(SpecialFiles, ADeviceIsNoProgram) {
  for (const auto& command : kCommands) {
    expect_refused(command, "/dev/null");
    expect_refused(command, "/dev/zero");
  }
}

TEST(SpecialFiles, ANamedPipeIsNoProgram) {
  TempDir d;
  std::string fifo = d.path + "/prog.nqc";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const auto& command : kCommands) expect_refused(command, fifo);
}

TEST(SpecialFiles, OneMissingOrAFolderIsExplainedAsBefore) {
  TempDir d;
  auto missing = run_rcxc({"run", d.path + "/none.nqc"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(missing.err.find("not a file (a device"), std::string::npos) << missing.err;
  auto folder = run_rcxc({"compile", d.path, "-o", d.path + "/p.rcx"});
  EXPECT_EQ(folder.exit_code, 1);
  EXPECT_EQ(folder.err.find("not a file (a device"), std::string::npos) << folder.err;
}

TEST(SpecialFiles, TheStandardInputIsStillRead) {
  TempDir d;
  auto compiled = run_rcxc({"compile", "-", "-o", d.path + "/p.rcx"}, kProgram);
  EXPECT_EQ(compiled.exit_code, 0) << compiled.err;
  auto ran = run_rcxc({"run", "-"}, kProgram);
  EXPECT_EQ(ran.exit_code, 0) << ran.err;
  auto listed = run_rcxc({"disasm", "-"}, kProgram);
  EXPECT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_NE(listed.out.find("task 0 main"), std::string::npos) << listed.out;
  auto formatted = run_rcxc({"format", "-"}, kProgram);
  EXPECT_EQ(formatted.exit_code, 0) << formatted.err;
  EXPECT_EQ(formatted.out, kProgram);
  // download reads the program before it looks for the tower: exit 3, no port.
  auto downloaded = run_rcxc({"download", "--port", d.path + "/no-such-tower", "-"}, kProgram);
  EXPECT_EQ(downloaded.exit_code, 3) << downloaded.err;
  // A regular file through /dev/stdin is a file.
  auto redirected = rcxc::test::run_process(
      {"/bin/sh", "-c", "'" RCXC_BINARY "' compile /dev/stdin -o '" + d.path + "/q.rcx' < '" + d.write("p.nqc", kProgram) + "'"});
  EXPECT_EQ(redirected.exit_code, 0) << redirected.err;
}

}  // namespace
