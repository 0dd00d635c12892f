// "Did you mean": the command, action or option a misspelt word of the
// command line stands for. CLI11 says only that a word was not expected, or
// that a subcommand is required.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rcxc::cli {

struct MisspellingHint {
  std::string word;  // as typed ("--fro=3", "compil")
  std::string text;  // "unknown option '--fro': did you mean '--for'?"
  bool command = false;  // the word stands where a command or action goes
  // The word after a misspelt option whose likely meaning takes a value
  // (`--prot usb`: usb), which the parser then finds unexpected too.
  std::optional<std::string> value;
};

// `app` is the whole command line's parser, `words` the command line after
// the program's name; the options of the deepest command the words name
// (and of the commands above it) and its actions are the candidates.
std::optional<MisspellingHint> misspelling_hint(const CLI::App& app, const std::vector<std::string>& words);

// Whether the hint accounts for a word the parser did not expect: the word
// itself or its value, or any word after an unknown command or action
// (`rcxc compil p.nqc`: p.nqc is unexpected only because compil is no
// command).
bool hint_explains(const MisspellingHint& hint, const std::string& unexpected);

// A word `--NAME=` with nothing after the '=' (`--listing=$EMPTY`): CLI11
// takes it as `--NAME` alone, so --listing= printed the listing and
// `--trace= p.nqc` took p.nqc as the trace's name. What to say, or nullopt.
// Words after `--` are not options.
std::optional<std::string> option_without_value(const std::vector<std::string>& words);

// CLI11's message for a parse error, in words a user reads at once where
// its own are cryptic ("--trace: At Most 1 required but received 2" is
// "--trace given 2 times: it takes one"; "-O: 1 required TEXT:{0,1,2,s}
// missing" is "-O needs a value: one of 0,1,2,s").
std::string parse_error_text(const CLI::ParseError& e);

// The names of `command`'s actions, a few lines of them, and where their
// descriptions are: printed after an unknown action instead of the whole
// help (80 lines for rcxc nxt, its telegram table included, in which the
// one line that named the mistake scrolled away).
std::string action_list(const CLI::App& command);

// Whether `e` is CLI11's "A subcommand is required": a command whose actions
// are subcommands (`rcxc nxt`) given none, or given a word that is none.
bool is_missing_action(const CLI::ParseError& e);

}  // namespace rcxc::cli
