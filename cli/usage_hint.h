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

}  // namespace rcxc::cli
