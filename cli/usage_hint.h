// "Did you mean": the command, action or option a misspelt word of the
// command line stands for. CLI11 says only that a word was not expected, or
// that a subcommand is required.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rcxc::cli {

// `app` is the whole command line's parser, `words` the command line after
// the program's name; the options of the deepest command the words name
// (and of the commands above it) and its actions are the candidates.
std::optional<std::string> misspelling_hint(const CLI::App& app, const std::vector<std::string>& words);

// CLI11's message for a parse error, in words a user reads at once where
// its own are cryptic ("--trace: At Most 1 required but received 2" is
// "--trace given 2 times: it takes one").
std::string parse_error_text(const CLI::ParseError& e);

// Whether `e` is CLI11's "A subcommand is required": a command whose actions
// are subcommands (`rcxc nxt`) given none, or given a word that is none.
bool is_missing_action(const CLI::ParseError& e);

}  // namespace rcxc::cli
