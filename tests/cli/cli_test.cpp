// The command line is a contract for scripts and IDEs: exit codes and where
// usage text goes are checked end to end against the real binary.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/support/process.h"

using rcxc::test::run_rcxc;

TEST(Cli, VersionPrintsNameAndVersion) {
  auto r = run_rcxc({"--version"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.rfind("rcxc ", 0), 0u) << r.out;
}

TEST(Cli, StartingLoadsNoUsbOrBluetoothLibrary) {
  // libusb (with libudev) is loaded when an NXT's USB port is opened, and of
  // BlueZ's library nothing is used: loading them cost every compile (docs/compiler.md).
  auto r = rcxc::test::run_process({"/bin/sh", "-c", std::string("LD_DEBUG=files exec '") + RCXC_BINARY +
                                                          "' compile - -o /dev/null < /dev/null"});
  EXPECT_NE(r.err.find("libc.so"), std::string::npos) << "LD_DEBUG said nothing: " << r.err.substr(0, 300);
  for (const char* library : {"libusb", "libudev", "libbluetooth"})
    EXPECT_EQ(r.err.find(library), std::string::npos) << library << "\n" << r.err.substr(0, 2000);
}

TEST(Cli, HelpListsSubcommands) {
  auto r = run_rcxc({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"compile", "run", "disasm"}) EXPECT_NE(r.out.find(sub), std::string::npos) << sub;
}

TEST(Cli, UnknownOptionIsUsageErrorOnStderr) {
  auto r = run_rcxc({"--no-such-option"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("--no-such-option"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Usage"), std::string::npos) << r.err;
}

TEST(Cli, UnknownSubcommandOptionShowsThatSubcommandsUsage) {
  auto r = run_rcxc({"run", "--bogus", "x.rcx"});
  EXPECT_EQ(r.exit_code, 2);
  // As `rcxc help run` shows it (it was "Usage: run [OPTIONS] FILE").
  EXPECT_NE(r.err.find("Usage: rcxc run [OPTIONS] FILE"), std::string::npos) << r.err;
  auto nested = run_rcxc({"nxt", "tone"});
  EXPECT_EQ(nested.exit_code, 2);
  EXPECT_NE(nested.err.find("Usage: rcxc nxt tone [OPTIONS] HZ MS"), std::string::npos) << nested.err;
}

// A misspelt command, action or option got only "The following arguments
// were not expected: prog.nqc --fro" (naming the file as unexpected too) or,
// for an NXT action, "A subcommand is required". Each now gets the word it
// most likely stands for, an option value (--port usb) not taken for one.
TEST(Cli, AMisspeltCommandActionOrOptionGetsADidYouMean) {
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"compiel", "p.nqc"}, "unknown command 'compiel': did you mean 'compile'?"},
      {{"run", "--fro", "10", "p.nqc"}, "unknown option '--fro': did you mean '--for'?"},
      {{"run", "p.nqc", "--scenaro=s.toml"}, "unknown option '--scenaro': did you mean '--scenario'?"},
      {{"nxt", "--timeout", "5", "motr", "A", "5"}, "unknown action 'motr': did you mean 'motor'?"},
      {{"nxt", "--port", "usb", "mailbox", "wrte", "1", "x"}, "unknown action 'wrte': did you mean 'write'?"},
      {{"nxt", "--prot", "usb", "info"}, "unknown option '--prot': did you mean '--port'?"},
  };
  for (const auto& [args, hint] : cases) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find("rcxc: " + hint), std::string::npos) << r.err;
  }
  // Nothing near: no guess.
  auto far = run_rcxc({"run", "--zzzzzz", "p.nqc"});
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
}

// An NXT action nothing like any got only "A subcommand is required", as if
// none had been given.
TEST(Cli, AnUnknownActionWithNothingNearIsNamed) {
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"nxt", "zzzzzz"}, "unknown action 'zzzzzz': the actions are listed below"},
      {{"nxt", "format"}, "unknown action 'format': every file on the brick is deleted by 'rcxc nxt erase-all --yes'"},
      {{"nxt", "volum", "2"}, "unknown action 'volum': did you mean 'volume'?"},
      {{"nxt", "mailbox", "zzzzzz", "1"}, "unknown action 'zzzzzz': the actions are listed below"},
      {{"zzzzzz"}, "unknown command 'zzzzzz': the commands are listed below"},
  };
  for (const auto& [args, said] : cases) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find("rcxc: " + said), std::string::npos) << r.err;
  }
  EXPECT_NE(run_rcxc({"zzzzzz"}).err.find("Usage: rcxc"), std::string::npos);
  EXPECT_NE(run_rcxc({"nxt", "mailbox", "zzzzzz", "1"}).err.find("the actions of rcxc nxt mailbox: write, read\n"),
            std::string::npos);
}

// An unknown NXT action printed the whole help of rcxc nxt, 93 lines with
// its telegram table, the line naming the mistake scrolled off the top. It
// is a few lines now: the word, a did-you-mean or what the word likely
// meant (`serve`: the virtual brick), and the actions' names.
TEST(Cli, AnUnknownNxtActionIsAShortErrorWithTheActionsNamed) {
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"nxt", "serve"}, "unknown action 'serve': a virtual NXT is served by 'rcxc nxt brick --pty'"},
      {{"nxt", "--port", "usb", "motr", "A", "5"}, "unknown action 'motr': did you mean 'motor'?"},
      {{"nxt", "delete", "x.rxe"}, "unknown action 'delete': a file on the brick is deleted by 'rcxc nxt rm NAME'"},
      {{"nxt", "zzzzzz"}, "unknown action 'zzzzzz': the actions are listed below"},
  };
  for (const auto& [args, said] : cases) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << args[1] << ": " << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err.rfind("rcxc: " + said + "\n", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("\nthe actions of rcxc nxt: info, battery, tone,"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(" bench, brick\n'rcxc help nxt' says what each does\n"), std::string::npos) << r.err;
    // The mistake, the 35 actions' names on five lines, where to read more.
    EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 7) << r.err;
    EXPECT_EQ(r.err.find("Usage:"), std::string::npos) << r.err;
  }
}

TEST(Cli, MissingSubcommandIsUsageError) {
  auto r = run_rcxc({});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("Usage"), std::string::npos);
}

// An empty value read as the option not given: `run --trace ''` ran
// without a trace and `--scenario ''` without inputs, both with exit 0;
// `--nxt ''` printed a whole run before saying the port was empty. A
// negative seed became 2^64 - 1.
TEST(Cli, AnEmptyValueOrANegativeSeedIsAUsageError) {
  rcxc::test::TempDir d;
  std::string p = d.write("p.nqc", "task main() { On(OUT_A); }\n");
  const std::vector<std::vector<std::string>> calls = {
      {"run", p, "--trace", ""},         {"run", p, "--scenario", ""},    {"run", p, "--nxt", ""},
      {"compare", p, "--scenario", ""},  {"compare", p, "--nqc-path", ""}, {"test", p, "--nqc-path", ""},
      {"remote", "--port", "", "alive"}, {"download", p, "--port", ""},   {"nxt", "--port", "", "info"},
      {"nxt", "brick", "--pty", "--scenario", ""},
      // `compile --listing ''` wrote no listing with exit 0; an empty FILE
      // said "rcxc disasm: : cannot open file", a PATH of test "no such file
      // or folder: " with nothing after it.
      {"compile", p, "--listing", ""},   {"disasm", ""},                  {"run", ""},
      {"download", "--port", "/dev/no-such-tower", ""}, {"compare", ""}, {"test", p, ""},
      {"run", p, "--seed", "-1"},        {"compare", p, "--seed", "-1"},   {"brick", "--pty", "--seed", "-2"}};
  for (const auto& args : calls) {
    auto r = run_rcxc(args, "", 10000);
    std::string call;
    for (const auto& a : args) call += " '" + a + "'";
    EXPECT_EQ(r.exit_code, 2) << call << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << call << ": " << r.out;
    bool said = r.err.find("needs a value, not ''") != std::string::npos ||
                r.err.find("is not a whole number 0 or more") != std::string::npos;
    EXPECT_TRUE(said) << call << ": " << r.err;
  }
  EXPECT_EQ(run_rcxc({"run", p, "--seed", "0", "--for", "10"}).exit_code, 0);
}

// A seed past 2^64 - 1 ran as 2^64 - 1 without a word (so 2^64 and
// 99999999999999999999 gave the same run as 18446744073709551615).
TEST(Cli, ASeedPastSixtyFourBitsIsAUsageError) {
  rcxc::test::TempDir d;
  std::string p = d.write("p.nqc", "task main() { On(OUT_A); }\n");
  for (const std::string seed : {"18446744073709551616", "99999999999999999999", "000000000000000000000018446744073709551616"})
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"run", p, "--seed", seed}, {"compare", p, "--seed", seed}, {"brick", "--pty", "--seed", seed}}) {
      auto r = run_rcxc(args, "", 10000);
      EXPECT_EQ(r.exit_code, 2) << args[0] << " " << seed << ": " << r.err;
      EXPECT_NE(r.err.find(seed.substr(seed.find_first_not_of('0')) + "' is more than 18446744073709551615"),
                std::string::npos)
          << r.err;
      EXPECT_TRUE(r.out.empty()) << r.out;
    }
  for (const std::string seed : {"18446744073709551615", "0018446744073709551615"})
    EXPECT_EQ(run_rcxc({"run", p, "--seed", seed, "--for", "10"}).exit_code, 0) << seed;
}

// CLI11 read a leading zero as octal: `--for 010` ran 8 ms, `--seed 010`
// was seed 8, `--for 09` was "Could not convert". Every whole number is
// decimal now.
TEST(Cli, LeadingZerosAreDecimalNotOctal) {
  rcxc::test::TempDir d;
  std::string p = d.write("p.nqc", "int x;\ntask main() { x = Random(1000); Wait(1000); }\n");
  auto time_and_x = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"run", p, "--report", "json"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out, nullptr, false);
    return j.is_discarded() ? std::pair<int, int>{-1, -1} : std::pair<int, int>{j["time_ms"], j["globals"]["x"]};
  };
  EXPECT_EQ(time_and_x({"--for", "010"}).first, 10);
  EXPECT_EQ(time_and_x({"--for", "09"}).first, 9);
  EXPECT_EQ(time_and_x({"--for", "5", "--seed", "010"}).second, time_and_x({"--for", "5", "--seed", "10"}).second);
  EXPECT_NE(time_and_x({"--for", "5", "--seed", "010"}).second, time_and_x({"--for", "5", "--seed", "8"}).second);
  EXPECT_EQ(run_rcxc({"run", p, "--for", "000"}).exit_code, 2);  // still 0, still out of range
  EXPECT_EQ(run_rcxc({"nxt", "--port", "/dev/no-such-nxt", "tone", "0440", "0100"}).exit_code, 3);  // HZ, MS taken
}

// `rcxc lsp --stdlib-dir FILE` started, and every go to definition into the
// standard library then answered null with nothing said anywhere.
// `rcxc lsp -D 1X` (or -Dtask) started a server that compiled every
// document with that macro; the compiling commands refuse it.
TEST(Cli, AnLspMacroNameThatCannotBeOneIsAUsageError) {
  for (const std::string option : {"-D1X", "-Dtask=1", "-Uacquire"}) {
    auto r = run_rcxc({"lsp", option});
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.err;
    EXPECT_NE(r.err.find("rcxc lsp: " + option + ": "), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

TEST(Cli, AnLspStdlibDirThatIsAFileIsAUsageError) {
  rcxc::test::TempDir d;
  std::string file = d.write("not-a-folder", "x");
  auto r = run_rcxc({"lsp", "--stdlib-dir", file});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file + " is a file, not a folder"), std::string::npos) << r.err;
}

// Every whole-number option and argument of every command, given a value out
// of range, past 32 and 64 bits, no number or nothing: a usage error naming
// the option and what it takes. A number past the variable's type got
// CLI11's bare "Could not convert: HZ = 99999999999", naming no range.
TEST(Cli, EveryNumberOptionNamesItselfAndItsRangeForABadValue) {
  rcxc::test::TempDir d;
  std::string p = d.write("p.nqc", "task main() { On(OUT_A); }\n");
  const std::string nowhere = "/dev/no-such-port";
  // {arguments with X where the value goes, the name the message starts with}
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"run", p, "--for", "X"}, "--for"},
      {{"run", p, "--instruction-us", "X"}, "--instruction-us"},
      {{"run", p, "--seed", "X"}, "--seed"},
      {{"compare", p, "--for", "X"}, "--for"},
      {{"compare", p, "--instruction-us", "X"}, "--instruction-us"},
      {{"compare", p, "--seed", "X"}, "--seed"},
      {{"compile", p, "-o", "/dev/null", "--max-errors", "X"}, "--max-errors"},
      {{"download", p, "--port", nowhere, "--program", "X"}, "--program"},
      {{"download", p, "--port", nowhere, "--retries", "X"}, "--retries"},
      {{"remote", "--port", nowhere, "--retries", "X", "alive"}, "--retries"},
      {{"format", p, "--indent", "X"}, "--indent"},
      {{"test", p, "-j", "X"}, "--jobs"},
      {{"brick", "--pty", "--seed", "X"}, "--seed"},
      {{"nxt", "--port", nowhere, "--timeout", "X", "battery"}, "--timeout"},
      {{"nxt", "--port", nowhere, "tone", "X", "100"}, "HZ"},
      {{"nxt", "--port", nowhere, "tone", "440", "X"}, "MS"},
      {{"nxt", "--port", nowhere, "motor", "A", "X"}, "POWER"},
      {{"nxt", "--port", nowhere, "motor", "A", "50", "--limit", "X"}, "--limit"},
      {{"nxt", "--port", nowhere, "mailbox", "write", "X", "text"}, "BOX"},
      {{"nxt", "--port", nowhere, "mailbox", "write", "1", "--int", "X"}, "--int"},
      {{"nxt", "--port", nowhere, "mailbox", "read", "X"}, "BOX"},
      {{"nxt", "--port", nowhere, "bench", "--count", "X"}, "--count"},
      {{"brick", "--pty", "--noise", "X"}, "--noise"},
  };
  for (const auto& [shape, name] : cases)
    for (const std::string value : {"99999999999", "-99999999999", "99999999999999999999", "-1e3", "1e999", "abc", ""}) {
      // The 64-bit ones (--for up to 2^40 ms, --seed) take 99999999999.
      if (value == "99999999999" && (name == "--for" || name == "--seed")) continue;
      std::vector<std::string> args = shape;
      std::replace(args.begin(), args.end(), std::string("X"), value);
      auto r = run_rcxc(args, "", 10000);
      std::string call;
      for (const auto& a : args) call += " '" + a + "'";
      EXPECT_EQ(r.exit_code, 2) << call << ": " << r.err;
      EXPECT_TRUE(r.out.empty()) << call << ": " << r.out;
      EXPECT_EQ(r.err.find("Could not convert"), std::string::npos) << call << ": " << r.err;
      // The first line names the option and says what it takes.
      std::string first = r.err.substr(0, r.err.find('\n'));
      EXPECT_NE(first.find(name + ": '" + value + "' is "), std::string::npos) << call << ": " << first;
      bool says_what = first.find(" is outside ") != std::string::npos ||
                       first.find(" is not a whole number") != std::string::npos ||
                       first.find(" is not a number") != std::string::npos ||
                       first.find(" is more than ") != std::string::npos;
      EXPECT_TRUE(says_what) << call << ": " << first;
    }
  // A float's range: 1e39 was converted to float, which is undefined behaviour.
  for (const std::string value : {"1e39", "-1e999", "abc", "nan", ""}) {
    auto r = run_rcxc({"nxt", "--port", nowhere, "mailbox", "write", "1", "--float", value}, "", 10000);
    EXPECT_EQ(r.exit_code, 2) << value << ": " << r.err;
    EXPECT_EQ(r.err.find("rcxc: --float: '" + value + "' is "), 0u) << value << ": " << r.err;
  }
}

// `rcxc nxt --json` with a value the command-line parser refuses printed
// only the usage text on stderr: a script that asked for JSON got an empty
// stdout, where every other failure gives it {"ok": false, ...} (docs/nxt.md).
TEST(Cli, NxtJsonGetsTheUsageErrorAsJsonToo) {
  const std::string nowhere = "/dev/no-such-port";
  // {arguments, the action, the start of the error}
  const std::vector<std::tuple<std::vector<std::string>, std::string, std::string>> cases = {
      {{"nxt", "--json", "--port", nowhere, "tone", "99999", "100"}, "tone", "HZ: '99999' is "},
      {{"nxt", "--port", nowhere, "--json", "--timeout", "abc", "battery"}, "battery", "--timeout: 'abc' is "},
      {{"nxt", "--json", "--port", nowhere, "mailbox", "write", "1", "--float", "1e39"}, "mailbox write", "--float: '1e39' is "},
      {{"nxt", "--json", "--port", nowhere, "mailbox", "wrte", "1", "x"}, "mailbox", "unknown action 'wrte'"},
      {{"nxt", "--json", "--port=", "info"}, "", "--port="},
      {{"nxt", "--json"}, "", "an action is required"},
  };
  for (const auto& [args, action, error] : cases) {
    std::string call;
    for (const auto& a : args) call += " '" + a + "'";
    auto r = run_rcxc(args, "", 10000);
    EXPECT_EQ(r.exit_code, 2) << call << ": " << r.err;
    // An unknown action gets the actions' names instead (the test above).
    if (error != "--port=" && !error.starts_with("unknown action")) {
      EXPECT_NE(r.err.find("Usage:"), std::string::npos) << call << ": " << r.err;
    }
    auto j = nlohmann::json::parse(r.out, nullptr, false);
    ASSERT_TRUE(j.is_object()) << call << ": stdout is '" << r.out << "'";
    EXPECT_EQ(j["ok"], false) << call;
    EXPECT_EQ(j["action"], action) << call;
    EXPECT_EQ(j["error"].get<std::string>().find(error), 0u) << call << ": " << j.dump();
  }
  // Without --json (or with it only as a value after `--`) stdout stays empty.
  auto plain = run_rcxc({"nxt", "--port", nowhere, "tone", "99999", "100"}, "", 10000);
  EXPECT_EQ(plain.exit_code, 2);
  EXPECT_EQ(plain.out, "");
}

// An unknown NXT action was "A subcommand is required" and then the hint
// naming it, as if none had been given and then one; an option given
// twice was CLI11's "--trace: At Most 1 required but received 2".
TEST(Cli, AParseErrorIsSaidOnceInPlainWords) {
  auto action = run_rcxc({"nxt", "zzzzzz"});
  EXPECT_EQ(action.exit_code, 2);
  EXPECT_EQ(action.err.find("A subcommand is required"), std::string::npos) << action.err;
  EXPECT_NE(action.err.find("rcxc: unknown action 'zzzzzz'"), std::string::npos) << action.err;
  auto twice = run_rcxc({"run", "p.nqc", "--trace", "a.vcd", "--trace", "b.vcd"});
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("rcxc: --trace given 2 times: it takes one\n"), std::string::npos) << twice.err;
  EXPECT_EQ(twice.err.find("At Most"), std::string::npos) << twice.err;
  // A missing FILE is still said beside a misspelt option's hint.
  auto misspelt = run_rcxc({"run", "--fro"});
  EXPECT_EQ(misspelt.exit_code, 2);
  EXPECT_NE(misspelt.err.find("rcxc: unknown option '--fro': did you mean '--for'?"), std::string::npos)
      << misspelt.err;
  EXPECT_NE(misspelt.err.find("FILE is required"), std::string::npos) << misspelt.err;
  // CLI11's "argument was not expected" said the word the hint names
  // again; it stays only for a word no hint accounts for.
  for (std::vector<std::string> args : std::vector<std::vector<std::string>>{
           {"run", "--fro", "p.nqc"}, {"compil", "p.nqc"}, {"zzzzzz"}, {"nxt", "--prot", "usb", "info"}}) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << args[0];
    EXPECT_EQ(r.err.find("not expected"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("rcxc: unknown ", 0), 0u) << r.err;
  }
  // (`compile` takes one FILE; `run` takes several, one brick each.)
  auto more = run_rcxc({"compile", "--lisitng", "p.nqc", "q.nqc"});
  EXPECT_EQ(more.exit_code, 2);
  EXPECT_NE(more.err.find("not expected"), std::string::npos) << more.err;
  EXPECT_NE(more.err.find("q.nqc"), std::string::npos) << more.err;
  EXPECT_NE(more.err.find("unknown option '--lisitng': did you mean '--listing'?"), std::string::npos) << more.err;
  // `--NAME=` was `--NAME` to CLI11: --listing= printed the listing with
  // exit 0, and --trace= took the next word as the trace's name.
  rcxc::test::TempDir d;
  std::string p = d.write("p.nqc", "task main() { On(OUT_A); }\n");
  for (std::vector<std::string> args : std::vector<std::vector<std::string>>{
           {"compile", p, "--listing=", "-o", d.path + "/p.rcx"}, {"run", "--trace=", p}, {"nxt", "--port=", "info"}}) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << args[1];
    EXPECT_EQ(r.out, "") << args[1];
    EXPECT_NE(r.err.find(": nothing after '=' (give --"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(d.path + "/p.rcx"));
  EXPECT_EQ(run_rcxc({"compile", p, "--listing", "-o", d.path + "/p.rcx"}).exit_code, 0);
  // An option without its value: CLI11 said "-D: 1 required TEXT missing".
  auto bare = run_rcxc({"run", "p.nqc", "-D"});
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_NE(bare.err.find("rcxc: -D needs a value\n"), std::string::npos) << bare.err;
  EXPECT_EQ(bare.err.find("required TEXT missing"), std::string::npos) << bare.err;
  auto level = run_rcxc({"compile", "p.nqc", "-O"});
  EXPECT_EQ(level.exit_code, 2);
  EXPECT_NE(level.err.find("rcxc: -O needs a value: one of 0,1,2,s\n"), std::string::npos) << level.err;
  auto none = run_rcxc({"nxt"});
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("rcxc: an action is required: the actions are listed below"), std::string::npos)
      << none.err;
}
