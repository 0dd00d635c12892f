// `rcxc help`, `rcxc version`, and the documents that must list every
// command and option: the man page docs/rcxc.1 and the bash and zsh
// completion scripts. The commands and options are read from rcxc's own
// --help output, so a new one fails here until it is documented.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "tests/support/process.h"

namespace rcxc::test {
namespace {

// The commands `rcxc --help` lists.
std::vector<std::string> commands() {
  std::string help = run_rcxc({"--help"}).out;
  std::vector<std::string> out;
  auto at = help.find("Subcommands:");
  std::istringstream lines(help.substr(at == std::string::npos ? help.size() : at));
  std::string line;
  std::getline(lines, line);
  std::regex entry(R"(^  ([a-z]+)\s)");
  std::smatch m;
  while (std::getline(lines, line))
    if (std::regex_search(line, m, entry)) out.push_back(m[1]);
  return out;
}

// The options `rcxc COMMAND --help` lists (-h/--help left out).
std::vector<std::string> options(const std::string& command) {
  std::string help = run_rcxc({command, "--help"}).out;
  std::vector<std::string> out;
  std::regex option(R"(^  (--?[A-Za-z0-9][-A-Za-z0-9]*)(,(--[-a-z0-9]+))?)");
  std::istringstream lines(help);
  std::string line;
  std::smatch m;
  while (std::getline(lines, line))
    if (std::regex_search(line, m, option)) {
      std::string name = m[3].matched ? m[3].str() : m[1].str();
      if (name != "--help") out.push_back(name);
    }
  return out;
}

TEST(Help, HelpAndVersionCommands) {
  auto all = run_rcxc({"help"});
  EXPECT_EQ(all.exit_code, 0);
  EXPECT_EQ(all.out, run_rcxc({"--help"}).out);
  auto one = run_rcxc({"help", "compile"});
  EXPECT_EQ(one.exit_code, 0);
  EXPECT_NE(one.out.find("Usage: rcxc compile"), std::string::npos) << one.out;
  EXPECT_EQ(one.out, run_rcxc({"compile", "--help"}).out);
  auto bad = run_rcxc({"help", "compiel"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("no command 'compiel'"), std::string::npos) << bad.err;
  auto version = run_rcxc({"version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out, run_rcxc({"--version"}).out);
  EXPECT_EQ(version.out.rfind("rcxc ", 0), 0u);
}

// README and the man page name `rcxc nqc` as a command, yet `rcxc help nqc`
// said "there is no command 'nqc'". It shows nqc mode's own summary.
TEST(Help, HelpNqcShowsTheNqcModeSummary) {
  auto r = run_rcxc({"help", "nqc"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, run_rcxc({"nqc", "-help"}).out);
  EXPECT_NE(r.out.find("usage: nqc [options]"), std::string::npos) << r.out;
  EXPECT_NE(run_rcxc({"help", "compiel"}).err.find("(commands: nqc, compile,"), std::string::npos);
}

// The NXT's actions are commands of their own (`rcxc nxt brick --help`), and
// `rcxc help nxt brick` was refused: "The following argument was not
// expected: brick", exit 2.
TEST(Help, HelpDescribesAnActionOfACommand) {
  for (std::vector<std::string> words : {std::vector<std::string>{"nxt", "brick"}, {"nxt", "mailbox", "write"}}) {
    std::vector<std::string> help_args{"help"};
    help_args.insert(help_args.end(), words.begin(), words.end());
    words.push_back("--help");
    auto r = run_rcxc(help_args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, run_rcxc(words).out);
  }
  EXPECT_NE(run_rcxc({"help", "nxt", "brick"}).out.find("Usage: rcxc nxt brick"), std::string::npos);
  auto fly = run_rcxc({"help", "nxt", "fly"});
  EXPECT_EQ(fly.exit_code, 2);
  EXPECT_NE(fly.err.find("'rcxc nxt' has no action 'fly' (actions: info, battery,"), std::string::npos) << fly.err;
  auto none = run_rcxc({"help", "compile", "x"});
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("'rcxc compile' has no actions"), std::string::npos) << none.err;
  EXPECT_EQ(run_rcxc({"help", "nqc", "x"}).exit_code, 2);
}

// `rcxc COMMAND ...` registers that command alone (cli/main.cpp, for
// startup time); `rcxc help COMMAND` registers every command. Both must
// describe the command alike, so no command depends on another's options.
TEST(Help, ACommandAloneDescribesItselfAsAmongAll) {
  auto names = commands();
  ASSERT_GE(names.size(), 10u);
  for (const auto& name : names) {
    auto alone = run_rcxc({name, "--help"});
    auto among_all = run_rcxc({"help", name});
    EXPECT_EQ(alone.exit_code, 0) << name;
    EXPECT_EQ(alone.out, among_all.out) << name;
  }
}

// The help line of an option that takes a number says what it is when left
// out, as docs/link.md and docs/nxt.md say it; `--retries INT  Retries per
// request` left a user guessing whether download tries 5 times or 30.
TEST(Help, NumberOptionsSayTheirDefaults) {
  struct Expected {
    std::vector<std::string> command;
    std::string option;
    std::string default_text;
  };
  const Expected expected[] = {
      {{"download"}, "--program", "(default 1)"},  {{"download"}, "--retries", "(default 30)"},
      {{"remote"}, "--retries", "(default 5)"},    {{"nxt"}, "--timeout", "(default 1000)"},
      {{"compare"}, "--seed", "(default 1)"},      {{"brick"}, "--seed", "(default 1)"},
      {{"run"}, "--seed", "(default 1)"},          {{"compare"}, "--for", "(default 20000)"},
      {{"nxt", "bench"}, "--count", "(default 200)"},
  };
  for (const auto& e : expected) {
    std::vector<std::string> args = e.command;
    args.push_back("--help");
    std::string help = run_rcxc(args).out;
    auto at = help.find("  " + e.option + " ");
    ASSERT_NE(at, std::string::npos) << e.command[0] << " " << e.option;
    std::string line = help.substr(at, help.find('\n', at) - at);
    EXPECT_NE(line.find(e.default_text), std::string::npos) << e.command[0] << ": " << line;
  }
}

TEST(Help, TheManPageCoversEveryCommandAndOption) {
  std::string man = read_text_file(RCXC_SOURCE_DIR "/docs/rcxc.1");
  // groff escapes '-' as '\-' in option names.
  auto unescape = [](std::string s) { return std::regex_replace(s, std::regex(R"(\\-)"), "-"); };
  std::string text = unescape(man);
  auto cmds = commands();
  ASSERT_GE(cmds.size(), 9u);
  auto compile = options("compile");
  for (const char* o : {"--output", "-I", "-n", "--listing", "--max-errors"})
    EXPECT_NE(std::find(compile.begin(), compile.end(), o), compile.end()) << o;
  for (const auto& c : cmds) {
    EXPECT_NE(text.find(".SS \"rcxc " + c), std::string::npos) << "docs/rcxc.1 has no section for " << c;
    for (const auto& o : options(c))
      EXPECT_NE(text.find(o), std::string::npos) << "docs/rcxc.1 does not mention " << c << " " << o;
  }
  auto groff = run_process({"/bin/sh", "-c", "command -v groff"});
  if (groff.exit_code != 0) GTEST_SKIP() << "groff is not installed: the page's markup is not checked";
  auto r = run_process({groff.out.substr(0, groff.out.find('\n')), "-man", "-Tutf8", "-ww", "-z", RCXC_SOURCE_DIR "/docs/rcxc.1"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
}

TEST(Help, CompletionScriptsKnowEveryCommandAndOption) {
  std::string bash = read_text_file(RCXC_SOURCE_DIR "/completions/rcxc.bash");
  std::string zsh = read_text_file(RCXC_SOURCE_DIR "/completions/_rcxc");
  for (const auto& c : commands()) {
    EXPECT_NE(bash.find(" " + c), std::string::npos) << "rcxc.bash lacks " << c;
    EXPECT_NE(zsh.find("'" + c + ":"), std::string::npos) << "_rcxc lacks " << c;
    for (const auto& o : options(c)) {
      EXPECT_NE(bash.find(o), std::string::npos) << "rcxc.bash lacks " << c << " " << o;
      EXPECT_NE(zsh.find(o), std::string::npos) << "_rcxc lacks " << c << " " << o;
    }
  }
}

TEST(Help, BashCompletesCommandsOptionsAndFiles) {
  TempDir dir;
  dir.write("robot.nqc", "task main() {}\n");
  dir.write("notes.txt", "");
  auto complete = [&](const std::string& words, int cword) {
    std::string script = "cd '" + dir.path + "' && source '" RCXC_SOURCE_DIR "/completions/rcxc.bash' && COMP_WORDS=(" +
                         words + ") && COMP_CWORD=" + std::to_string(cword) +
                         " && { _rcxc; printf '%s\\n' \"${COMPREPLY[@]}\"; }";
    auto r = run_process({"/bin/sh", "-c", "exec bash --norc -c \"$0\"", script});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.out;
  };
  EXPECT_EQ(complete("rcxc co", 1), "compile\ncompare\n");
  EXPECT_EQ(complete("rcxc compile --li", 2), "--listing\n");
  EXPECT_EQ(complete("rcxc compile ''", 2), "robot.nqc\n");  // not notes.txt
  EXPECT_EQ(complete("rcxc help ls", 2), "lsp\n");
  EXPECT_EQ(complete("rcxc remote ba", 2), "battery\n");
}

}  // namespace
}  // namespace rcxc::test
