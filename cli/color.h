// --color=auto|always|never, for every command that prints diagnostics.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace rcxc::cli {

// Adds --color to `cmd`, storing "auto", "always" or "never" in `when`.
CLI::Option* add_color_option(CLI::App* cmd, std::string& when);

// Whether diagnostics on standard error get colours: "always", or "auto"
// when standard error is a terminal (not TERM=dumb, no NO_COLOR set).
bool color_on_stderr(const std::string& when);

}  // namespace rcxc::cli
