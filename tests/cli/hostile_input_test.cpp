// Hostile inputs end cleanly (issue 21): each of these once crashed, ran
// out of memory or took seconds to minutes. Every one must now exit 1 with
// a message saying what limit it hit; the timeouts only catch a hang.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>

#include "tests/support/process.h"

using rcxc::test::ProcessResult;
using rcxc::test::run_process;
using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

constexpr int kHangMs = 30000;

std::string repeat(const std::string& s, int n) {
  std::string out;
  out.reserve(s.size() * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

ProcessResult compile(const TempDir& d, const std::string& source, const std::string& level = "-O2") {
  return run_rcxc({"compile", level, d.write("p.nqc", source), "-o", d.path + "/p.rcx"}, "", kHangMs);
}

// `rcxc test` reports on stdout, the others on stderr.
void expect_error(const ProcessResult& r, const std::string& message) {
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 1) << r.err.substr(0, 500);
  EXPECT_NE((r.err + r.out).find(message), std::string::npos) << r.err.substr(0, 500) << r.out.substr(0, 500);
}

// A chain of `depth` subroutines, each calling the one before twice.
std::string sub_chain(int depth) {
  std::string s = "int x;\nsub s0() { x += 1; }\n";
  for (int i = 1; i < depth; ++i) s += fmt::format("sub s{}() {{ s{}(); s{}(); }}\n", i, i - 1, i - 1);
  return s + fmt::format("task main() {{ s{}(); }}\n", depth - 1);
}

}  // namespace

TEST(HostileInput, SeventyThousandNestedBlocks) {
  TempDir d;
  auto r = compile(d, "task main() {" + repeat("{", 70000) + repeat("}", 70000) + "}\n");
  // The 3201st bracket: '{' of main is the first, at column 13.
  expect_error(r, "p.nqc:1:3213: error: brackets nested more than 3200 deep");
}

TEST(HostileInput, HundredThousandPrefixOperators) {
  TempDir d;
  expect_error(compile(d, "int x; task main() { x = " + repeat("- ", 100000) + "x; }\n"),
               "error: nested more than 3200 levels deep");
}

TEST(HostileInput, TwoHundredThousandTermSum) {
  TempDir d;
  expect_error(compile(d, "int x; task main() { x = x" + repeat("+x", 199999) + "; }\n"),
               "error: nested more than 3200 levels deep");
}

TEST(HostileInput, HundredThousandChainedIfs) {
  TempDir d;
  expect_error(compile(d, "int x; task main() { " + repeat("if (x) ", 100000) + "x = 1; }\n"),
               "error: nested more than 3200 levels deep");
}

TEST(HostileInput, HundredThousandChainedAssignments) {
  TempDir d;
  expect_error(compile(d, "int x; task main() { " + repeat("x = ", 100000) + "1; }\n"),
               "error: nested more than 3200 levels deep");
}

TEST(HostileInput, ADeepGlobalInitialiserToo) {
  TempDir d;
  expect_error(compile(d, "int x = " + repeat("~", 5000) + "1; task main() { }\n"),
               "error: nested more than 3200 levels deep");
}

TEST(HostileInput, DeeplyParenthesisedIfExpression) {
  TempDir d;
  expect_error(compile(d, "#if " + repeat("(", 100000) + "1" + repeat(")", 100000) + "\n#endif\ntask main() {}\n"),
               "p.nqc:1:261: error: #if expression nested too deeply (more than 512 levels)");
  expect_error(compile(d, "#if " + repeat("!", 100000) + "1\n#endif\ntask main() {}\n"),
               "error: #if expression nested too deeply");
  expect_error(compile(d, "#if " + repeat("1 ? ", 100000) + "1" + repeat(" : 0", 100000) + "\n#endif\ntask main() {}\n"),
               "error: #if expression nested too deeply");
}

TEST(HostileInput, NestedFunctionLikeMacroCalls) {
  // 30 KB that once took 8 GB: each level copied the arguments of the
  // levels outside it.
  TempDir d;
  expect_error(compile(d, "#define F(x) x\nint y; task main() { y = " + repeat("F(", 10000) + "1" +
                              repeat(")", 10000) + "; }\n"),
               "error: macro calls nested too deeply inside the arguments of 'F'");
}

TEST(HostileInput, ReasonableNestingStillCompiles) {
  TempDir d;
  auto r = compile(d, "#define F(x) (x)\n#if " + repeat("(", 200) + "1" + repeat(")", 200) +
                          "\nint y; task main() { y = " + repeat("F(", 100) + "1" + repeat(")", 100) + "; " +
                          repeat("{ if (y) ", 300) + "y = 2;" + repeat("}", 300) + " y = y" + repeat("+y", 300) +
                          ";}\n#endif\n");
  EXPECT_EQ(r.exit_code, 0) << r.err.substr(0, 500);
}

TEST(HostileInput, DoublingSubroutineChains) {
  // Each link doubles the inlined code: 14 links once took 20 s (the copy
  // was moved into place block by block), 16 never ended.
  TempDir d;
  // 14 links inline to 40 KB: only -Os, which outlines the repeats, fits
  // them in a subroutine; -O2 says at once that it does not fit.
  EXPECT_EQ(compile(d, sub_chain(14), "-Os").exit_code, 0);
  expect_error(compile(d, sub_chain(14)), "p.nqc:16:6: error: task main is 40966 bytes long");
  expect_error(compile(d, sub_chain(16)), "p.nqc:16:5: error: sub s14 would grow past 131072 bytes");
  expect_error(compile(d, sub_chain(60)), "error: sub s");
}

TEST(HostileInput, EndlessFilesStopAtTheirCap) {
  TempDir d;
  expect_error(run_rcxc({"compile", "/dev/zero", "-o", d.path + "/p.rcx"}, "", kHangMs),
               "/dev/zero: larger than a source file may be (1 MiB)");
  expect_error(run_rcxc({"disasm", "/dev/zero"}, "", kHangMs), "/dev/zero: larger than a .rcx image may be (1 MiB)");
  expect_error(run_rcxc({"run", "/dev/urandom"}, "", kHangMs), "/dev/urandom: larger than a .rcx image may be");
  std::string prog = d.write("p.nqc", "task main() { }\n");
  expect_error(run_rcxc({"run", prog, "--scenario", "/dev/zero"}, "", kHangMs),
               "/dev/zero: larger than a scenario file may be (1 MiB)");
  expect_error(run_rcxc({"test", d.write("t.nqc", "// @scenario /dev/zero\ntask main() { }\n")}, "", kHangMs),
               "larger than a scenario file may be");
  expect_error(run_rcxc({"remote", "--port", "/dev/no-such-tower", "firmware", "/dev/zero"}, "", kHangMs),
               "/dev/zero: larger than a firmware file may be (1 MiB)");
}

TEST(HostileInput, EndlessStdinPipe) {
  TempDir d;
  auto r = run_process({"/bin/sh", "-c", fmt::format("yes | '{}' compile /dev/stdin -o '{}/p.rcx'", RCXC_BINARY, d.path)},
                       "", kHangMs);
  expect_error(r, "/dev/stdin: larger than a source file may be (1 MiB)");
}

TEST(HostileInput, FirmwareAddressesFromTheFileAreChecked) {
  // 19 bytes that wrote to an address taken from the file, and a record
  // whose 32-bit address had the top bit set.
  TempDir d;
  expect_error(run_rcxc({"remote", "--port", "/dev/no-such-tower", "firmware",
                         d.write("a.srec", "S1040000AA51\nS5030001FB\n")},
                        "", kHangMs),
               "line 1: data at 0x0..0x0 is outside the firmware's RAM 0x8000..0xffff");
  expect_error(run_rcxc({"remote", "--port", "/dev/no-such-tower", "firmware",
                         d.write("b.srec", "S306FFFFFFFFAA53\n")},
                        "", kHangMs),
               "line 1: data at 0xffffffff..0xffffffff is outside the firmware's RAM");
}

TEST(HostileInput, ARegularFileIsNotAPort) {
  // Such a port once had IR packets appended to it.
  TempDir d;
  std::string notes = d.write("notes.txt", "keep me\n");
  for (const char* action : {"alive", "battery"}) {
    auto r = run_rcxc({"remote", "--port", notes, action}, "", kHangMs);
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("notes.txt is a regular file, not a tower"), std::string::npos) << r.err;
  }
  auto r = run_process({"/usr/bin/env", "RCX_PORT=" + notes, RCXC_BINARY, "download", d.write("p.nqc", "task main() {}\n")},
                       "", kHangMs);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(d.read("notes.txt"), (std::vector<std::uint8_t>{'k', 'e', 'e', 'p', ' ', 'm', 'e', '\n'}));
  auto dir = run_rcxc({"remote", "--port", d.path, "alive"}, "", kHangMs);
  EXPECT_EQ(dir.exit_code, 3) << dir.err;
}
