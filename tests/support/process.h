// Runs the rcxc binary (or any command) for end-to-end tests and captures
// its exit code, stdout and stderr.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rcxc::test {

struct ProcessResult {
  int exit_code = -1;  // 128 + N when killed by signal N
  std::string out;
  std::string err;
  bool timed_out = false;  // killed (SIGKILL) after the time limit
  long max_rss_kb = 0;     // the child's peak resident memory (getrusage)
};

// Runs `argv` (argv[0] is the program path) with `stdin_text` on its stdin.
// With `timeout_ms` > 0 the process is killed when it has not ended by then;
// with `address_space_bytes` > 0 it runs under that RLIMIT_AS, so memory
// that grows without bound fails at once instead of filling the machine.
ProcessResult run_process(const std::vector<std::string>& argv, const std::string& stdin_text = "",
                          int timeout_ms = 0, std::size_t address_space_bytes = 0);

// Runs the rcxc binary under test with `args`.
ProcessResult run_rcxc(const std::vector<std::string>& args, const std::string& stdin_text = "", int timeout_ms = 0,
                       std::size_t address_space_bytes = 0);

// Whether this build runs under AddressSanitizer, whose shadow memory
// needs terabytes of address space and inflates the resident size: memory
// limits cannot be measured there.
bool built_with_asan();

// The CPU time, in seconds, this process spent running `f` (all threads).
// For limits that catch work growing out of bounds in-process: wall time
// counts whatever else the machine runs (a parallel build made a 4 s check
// take 25 s), CPU time only this process's work.
double cpu_seconds_for(const std::function<void()>& f);

// The nqc on the PATH, or "" when it is not installed.
std::string find_nqc();

// The whole content of the file at `path` ("" when it cannot be read).
std::string read_text_file(const std::string& path);

// Every .nqc file under `dir` (recursively), sorted; none when `dir` is
// not a folder (the corpus may be absent).
std::vector<std::string> nqc_programs_under(const std::string& dir);

// A fresh empty directory under the system temp dir, removed by the caller.
std::string make_temp_dir();

// A temporary folder for one test, removed with everything in it at the end.
struct TempDir {
  std::string path = make_temp_dir();
  TempDir() = default;
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir();
  // Writes a file in the folder and returns its path.
  std::string write(const std::string& name, const std::string& text) const;
  std::string write(const std::string& name, const std::vector<std::uint8_t>& bytes) const;
  std::vector<std::uint8_t> read(const std::string& name) const;
};

// `rcxc ARGS... EXTRA...` running in the background as a server that prints the path
// of its pseudo-terminal as its first stdout line (`rcxc brick --pty`, `rcxc
// nxt brick --pty`); waits at most 10 s for that line. stderr goes to
// `stderr_path` when given. Stopped with SIGINT, as a user would.
struct PtyServer {
  int pid = -1;
  int out = -1;
  std::string path;
  int exit_code = -1;

  PtyServer(std::vector<std::string> args, const std::vector<std::string>& extra, const std::string& stderr_path = "");
  PtyServer(const PtyServer&) = delete;
  PtyServer& operator=(const PtyServer&) = delete;
  // The server's exit code (128 + signal when a signal ended it).
  int stop();
  ~PtyServer() { stop(); }
};

}  // namespace rcxc::test
