// Property test of the command line: for every subcommand, a few hundred
// argument vectors built from a fixed seed (unknown options, missing values,
// empty strings, huge and negative numbers, directories, missing and binary
// files, repeated options) must each end promptly with an exit code the
// subcommand documents, a message on stderr when it fails, and never an
// "internal error", a signal or a hang. A failure prints the command to
// reproduce it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "tests/support/process.h"

using rcxc::test::ProcessResult;
using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

constexpr int kTimeoutMs = 10'000;  // far above any honest run below; only a hang reaches it

// What follows an option on the command line.
enum class Takes { Nothing, Number, Path, Text, OutputPath, Port };

struct OptionSpec {
  std::string name;
  Takes takes;
};

struct CommandSpec {
  std::string name;
  Takes positional;  // what the required positional argument is
  std::vector<OptionSpec> options;
  std::set<int> exit_codes;  // every code the subcommand may end with
  int vectors;               // how many argument vectors to try
  bool reports_on_stdout = false;  // test/compare: a failing run's report is its output
};

// Every path is relative: the children run in a temporary folder (see
// InTempDir), so whatever they write stays there.
const std::vector<std::string> kNumbers = {
    "0", "1", "-1", "5", "6", "255", "256", "-32768", "32767", "65536", "2147483647", "2147483648",
    "-2147483649", "9223372036854775807", "9223372036854775808", "-9223372036854775809",
    "18446744073709551616", "99999999999999999999999999", "1e3", "0x10", "nan", "inf", "-inf", "1.5",
    "", " ", "abc", "1099511627776"};
const std::vector<std::string> kTexts = {
    "", "-", "--", "=", "json", "text", "s", "0", "1", "error", "X", "X=1", "1X", "X=", "=1", "a b",
    "\xff\xfe", "%s%n", "\t", "usb", "alive", "-O", std::string(3000, 'a')};
const std::vector<std::string> kPaths = {
    "valid.nqc", "bad.nqc", "empty.nqc", "binary.bin", "binary.rcx", "binary.nqc", "valid.rcx",
    "valid.toml", "bad.toml", "dir", "dir.nqc", "dir.rcx", "missing.nqc", "missing.rcx", "missing",
    "", "-", ".", "nodir/x.nqc"};
const std::vector<std::string> kOutputPaths = {"out.rcx", "", "-", "dir", "nodir/out.rcx", "t.vcd", "t.json",
                                               "valid.nqc", ".", "out"};
// Never a serial device or "usb": a real tower, if one is plugged in, must
// not be touched by the test suite.
const std::vector<std::string> kPorts = {"missing-port", "dir", "", "nodir/port"};
const std::vector<std::string> kStrays = {"--bogus", "-Z", "--", "-", "--for=", "---", "-h", "--help", "=", "-1"};

const std::vector<CommandSpec>& commands() {
  static const std::vector<CommandSpec> specs = {
      {"compile",
       Takes::Path,
       {{"-o", Takes::OutputPath}, {"--output", Takes::OutputPath}, {"-I", Takes::Path}, {"-D", Takes::Text},
        {"-U", Takes::Text}, {"-n", Takes::Nothing}, {"-E", Takes::Nothing}, {"-W", Takes::Text},
        {"-w", Takes::Nothing}, {"-O", Takes::Text}, {"--listing", Takes::OutputPath}, {"-v", Takes::Nothing},
        {"--diagnostics", Takes::Text}, {"--max-errors", Takes::Number}},
       {0, 1, 2},
       300},
      {"run",
       Takes::Path,
       {{"--scenario", Takes::Path}, {"--for", Takes::Number}, {"--seed", Takes::Number}, {"--report", Takes::Text},
        {"--trace", Takes::OutputPath}, {"--instruction-us", Takes::Number}, {"-I", Takes::Path}, {"-D", Takes::Text},
        {"-U", Takes::Text}, {"-n", Takes::Nothing}, {"-O", Takes::Text}},
       {0, 1, 2},
       300},
      {"disasm",
       Takes::Path,
       {{"-I", Takes::Path}, {"-D", Takes::Text}, {"-U", Takes::Text}, {"-n", Takes::Nothing}, {"-O", Takes::Text}},
       {0, 1, 2},
       150},
      {"test",
       Takes::Path,
       {{"--nqc", Takes::Nothing}, {"--nqc-path", Takes::Path}, {"-v", Takes::Nothing}, {"-I", Takes::Path},
        {"-D", Takes::Text}, {"-U", Takes::Text}, {"-n", Takes::Nothing}, {"-O", Takes::Text}},
       {0, 1, 2},
       200,
       true},
      {"compare",
       Takes::Path,
       {{"--scenario", Takes::Path}, {"--nqc-path", Takes::Path}, {"--for", Takes::Number}, {"--seed", Takes::Number},
        {"--instruction-us", Takes::Number}, {"-I", Takes::Path}, {"-D", Takes::Text}, {"-U", Takes::Text},
        {"-n", Takes::Nothing}, {"-O", Takes::Text}},
       {0, 1, 2, 5},
       200,
       true},
      // --pty is left out: with good options the brick serves until stopped
      // (BrickPty below covers it with bad ones).
      {"brick",
       Takes::Nothing,
       {{"--noise", Takes::Number}, {"--seed", Takes::Number}, {"--fast", Takes::Nothing},
        {"--no-echo", Takes::Nothing}, {"-v", Takes::Nothing}},
       {0, 2},
       200},
      {"download",
       Takes::Path,
       {{"-I", Takes::Path}, {"-D", Takes::Text}, {"-U", Takes::Text}, {"-n", Takes::Nothing}, {"-O", Takes::Text},
        {"--port", Takes::Port}, {"--program", Takes::Number}, {"--run", Takes::Nothing},
        {"--retries", Takes::Number}, {"--no-sound", Takes::Nothing}, {"-v", Takes::Nothing}},
       {1, 2, 3, 4},
       200},
      {"remote",
       Takes::Text,
       {{"--port", Takes::Port}, {"--csv", Takes::Nothing}, {"--retries", Takes::Number}},
       {1, 2, 3, 4},
       200},
  };
  return specs;
}

const std::vector<std::string> kRemoteWords = {
    "alive", "versions", "battery", "run", "stop", "program", "message", "get", "var", "sensor", "timer",
    "datalog", "watch", "12:30", "25:99", "now", "sleep", "clear", "firmware", "binary.bin", "missing.srec",
    "raw", "10", "zz", "3", "-1", "256", "99999999999999999999", "", "\xff"};

class Generator {
 public:
  explicit Generator(std::uint32_t seed) : rng_(seed) {}

  std::vector<std::string> vector_for(const CommandSpec& c) {
    std::vector<std::string> args{c.name};
    // Mostly the positional the command needs, so that options are judged
    // too, not only the missing argument.
    if (c.positional != Takes::Nothing && below(8) != 0) {
      int words = c.name == "remote" ? 1 + below(3) : 1;
      for (int i = 0; i < words; ++i) args.push_back(value(c.positional, c.name));
    }
    int pieces = below(5);
    for (int i = 0; i < pieces; ++i) add_piece(c, args);
    if (c.name == "download" || c.name == "remote") {
      // The last --port wins or the repetition is refused; either way no
      // default (USB) port is opened.
      args.push_back("--port");
      args.push_back("missing-port");
    }
    return args;
  }

 private:
  int below(int n) { return static_cast<int>(rng_() % static_cast<std::uint32_t>(n)); }
  template <typename T>
  const T& pick(const std::vector<T>& v) { return v[static_cast<std::size_t>(below(static_cast<int>(v.size())))]; }

  std::string value(Takes t, const std::string& command) {
    switch (t) {
      case Takes::Nothing: return pick(kStrays);
      case Takes::Number: return pick(kNumbers);
      case Takes::Path: return pick(kPaths);
      case Takes::OutputPath: return pick(kOutputPaths);
      case Takes::Port: return pick(kPorts);
      case Takes::Text: return command == "remote" && below(4) != 0 ? pick(kRemoteWords) : pick(kTexts);
    }
    return {};
  }

  void add_piece(const CommandSpec& c, std::vector<std::string>& args) {
    int kind = below(10);
    if (kind < 2 || c.options.empty()) {
      // A stray word, or one more positional.
      args.push_back(kind == 0 ? pick(kStrays) : value(c.positional == Takes::Nothing ? Takes::Text : c.positional, c.name));
      return;
    }
    const OptionSpec& o = pick(c.options);
    int form = below(8);
    if (o.takes == Takes::Nothing || form == 0) {
      args.push_back(o.name);  // a flag, or an option whose value is missing
      if (form == 1) args.push_back(value(Takes::Text, c.name));  // a flag given a value
    } else if (form == 1) {
      args.push_back(o.name + "=" + value(o.takes, c.name));
    } else if (form == 2 && o.name.size() == 2) {
      args.push_back(o.name + value(o.takes, c.name));  // -O0, -DX=1, -Idir
    } else {
      args.push_back(o.name);
      args.push_back(value(o.takes, c.name));
    }
    if (below(6) == 0) args.push_back(args.back());  // repeated
  }

  std::mt19937 rng_;
};

std::string command_line(const std::vector<std::string>& args) {
  std::string s = "rcxc";
  for (const auto& a : args) s += " '" + a + "'";
  return s;
}

// The files the generated vectors name; the folder is the children's working
// directory for the test's duration.
class InTempDir {
 public:
  InTempDir() {
    dir_.write("valid.nqc", "task main() { int x = 3; OnFwd(OUT_A); Wait(10); Off(OUT_A); x += 1; }\n");
    dir_.write("bad.nqc", "task main() { x = ; }\n");
    dir_.write("empty.nqc", "");
    std::string binary;
    for (int i = 0; i < 512; ++i) binary.push_back(static_cast<char>((i * 37 + 11) & 0xff));
    for (const char* name : {"binary.bin", "binary.rcx", "binary.nqc"}) dir_.write(name, binary);
    dir_.write("valid.toml", "[[input]]\nat_ms = 5\nsensor = 1\nraw = 300\n");
    dir_.write("bad.toml", "[[input]\nat_ms = \"x\"\n");
    for (const char* name : {"dir", "dir.nqc", "dir.rcx"}) std::filesystem::create_directory(dir_.path + "/" + name);
    // A real image for the image readers: compiled by the binary under test.
    auto r = run_rcxc({"compile", dir_.path + "/valid.nqc", "-o", dir_.path + "/valid.rcx"}, "", kTimeoutMs);
    image_ok_ = r.exit_code == 0;
    old_ = std::filesystem::current_path();
    std::filesystem::current_path(dir_.path);
  }
  ~InTempDir() {
    std::error_code ec;
    std::filesystem::current_path(old_, ec);
  }
  InTempDir(const InTempDir&) = delete;
  InTempDir& operator=(const InTempDir&) = delete;
  bool image_ok() const { return image_ok_; }

 private:
  TempDir dir_;
  std::filesystem::path old_;
  bool image_ok_ = false;
};

void check_command(const CommandSpec& c, std::uint32_t seed) {
  InTempDir dir;
  ASSERT_TRUE(dir.image_ok()) << "rcxc compile valid.nqc failed";
  Generator gen(seed);
  int failures = 0;
  for (int i = 0; i < c.vectors && failures < 5; ++i) {
    auto args = gen.vector_for(c);
    ProcessResult r = run_rcxc(args, "", kTimeoutMs);
    std::string where = command_line(args) + "\n  exit " + std::to_string(r.exit_code) + "\n  stderr: " + r.err.substr(0, 400);
    bool ok = true;
    auto expect = [&](bool condition, const char* what) {
      if (condition) return;
      ADD_FAILURE() << what << ": " << where;
      ok = false;
    };
    expect(!r.timed_out, "no end within 10 s");
    // -h/--help anywhere is a successful request for help.
    bool help = std::any_of(args.begin(), args.end(), [](const std::string& a) { return a == "-h" || a == "--help"; });
    expect(c.exit_codes.count(r.exit_code) > 0 || (help && r.exit_code == 0), "an exit code the command does not document");
    bool said_why = !r.err.empty() || (c.reports_on_stdout && !r.out.empty());
    expect(r.exit_code == 0 || said_why, "a failure without a message on stderr");
    expect(r.err.find("internal error") == std::string::npos, "an internal error");
    expect(r.err.find("terminate called") == std::string::npos, "an uncaught exception");
    if (!ok) ++failures;
  }
}

}  // namespace

TEST(CliProperty, Compile) { check_command(commands()[0], 101); }
TEST(CliProperty, Run) { check_command(commands()[1], 202); }
TEST(CliProperty, Disasm) { check_command(commands()[2], 303); }
TEST(CliProperty, Test) { check_command(commands()[3], 404); }
TEST(CliProperty, Compare) { check_command(commands()[4], 505); }
TEST(CliProperty, Brick) { check_command(commands()[5], 606); }
TEST(CliProperty, Download) { check_command(commands()[6], 707); }
TEST(CliProperty, Remote) { check_command(commands()[7], 808); }

// The brick with --pty serves until stopped, so it is tried here only with a
// --noise that is not a probability: each must be refused at once.
TEST(CliProperty, BrickPtyRefusesEveryNoiseThatIsNotAProbability) {
  for (const auto& noise : kNumbers) {
    if (noise == "0" || noise == "1") continue;
    auto r = run_rcxc({"brick", "--pty", "--noise", noise}, "", kTimeoutMs);
    EXPECT_FALSE(r.timed_out) << "--noise '" << noise << "' served";
    EXPECT_EQ(r.exit_code, 2) << "--noise '" << noise << "': " << r.err;
    EXPECT_FALSE(r.err.empty()) << noise;
  }
}
