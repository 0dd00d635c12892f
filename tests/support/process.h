// Runs the rcxc binary (or any command) for end-to-end tests and captures
// its exit code, stdout and stderr.
#pragma once

#include <string>
#include <vector>

namespace rcxc::test {

struct ProcessResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs `argv` (argv[0] is the program path) with `stdin_text` on its stdin.
ProcessResult run_process(const std::vector<std::string>& argv, const std::string& stdin_text = "");

// Runs the rcxc binary under test with `args`.
ProcessResult run_rcxc(const std::vector<std::string>& args, const std::string& stdin_text = "");

// A fresh empty directory under the system temp dir, removed by the caller.
std::string make_temp_dir();

}  // namespace rcxc::test
