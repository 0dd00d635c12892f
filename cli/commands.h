// Each subcommand of `rcxc` lives in its own file and registers itself here.
// A subcommand's callback stores the process exit code in `exit_code`.
#pragma once

#include <CLI/CLI.hpp>

namespace rcxc::cli {

// Exit codes shared by every subcommand (documented in README.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // the input was bad or the run failed
inline constexpr int kExitUsage = 2;    // the command line was bad

void register_compile(CLI::App& app, int& exit_code);
void register_run(CLI::App& app, int& exit_code);
void register_disasm(CLI::App& app, int& exit_code);

}  // namespace rcxc::cli
