#include "verify/external_nqc.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
#include <thread>

namespace rcx::semtest {
namespace {

constexpr std::size_t kLogBytes = 64 * 1024;

struct Log {
  std::string text;  // at most the first kLogBytes (a runaway nqc may write more)
  bool cut = false;  // there was more
};

// nqc's messages.
Log slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text(kLogBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  bool cut = text.size() > kLogBytes;
  if (cut) text.resize(kLogBytes);
  return {std::move(text), cut};
}

// What nqc printed, as it may go to a terminal: its lines stay lines, and
// other control bytes (an escape sequence quoted from a source line, binary
// junk from something that is no nqc) become \xNN.
std::string shown_log(const std::string& log) {
  std::string out;
  for (char ch : log) {
    auto c = static_cast<unsigned char>(ch);
    if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7f)
      out += fmt::format("\\x{:02x}", c);
    else
      out += ch;
  }
  return out;
}

// The command as a shell would take it back: words with anything but
// letters, digits and -_./=+:, in single quotes, control bytes as \xNN.
std::string shown_command(const std::vector<char*>& argv) {
  std::string out;
  for (const char* arg : argv) {
    if (!arg) break;
    std::string_view a(arg);
    bool plain = !a.empty();
    for (char c : a)
      if (!std::isalnum(static_cast<unsigned char>(c)) && std::string_view("-_./=+:,").find(c) == std::string_view::npos)
        plain = false;
    if (!out.empty()) out += ' ';
    if (plain) {
      out += a;
      continue;
    }
    out += '\'';
    for (char c : a) {
      auto u = static_cast<unsigned char>(c);
      if (c == '\'') out += "'\\''";
      else if (u < 0x20 || u == 0x7f) out += fmt::format("\\x{:02x}", u);
      else out += c;
    }
    out += '\'';
  }
  return out;
}

// nqc reports errors as
//   # Error: <message>
//   File "<file>" ; line <N>
// (warnings say "# Warning:"); the pairs may come in either order.
std::vector<CompilerMessage> parse_nqc_messages(const std::string& text) {
  std::vector<CompilerMessage> out;
  std::istringstream in(text);
  std::string line;
  int pending_line = 0;
  while (std::getline(in, line)) {
    auto l = line.find("; line ");
    if (line.rfind("File \"", 0) == 0 && l != std::string::npos) {
      pending_line = std::atoi(line.c_str() + l + 7);
      if (!out.empty() && out.back().line == 0) out.back().line = pending_line;
      continue;
    }
    for (auto [tag, error] : {std::pair{"# Error: ", true}, std::pair{"# Warning: ", false}}) {
      if (line.rfind(tag, 0) == 0) out.push_back({error, 0, line.substr(std::string(tag).size())});
    }
  }
  return out;
}

struct Child {
  bool started = false;
  bool timed_out = false;
  int status = 0;
};

// An AddressSanitizer build (the asan preset) reserves terabytes of address
// space, and so do the stand-ins for nqc its tests run (rcxc itself):
// there the address-space limit is left off, the time limit kept.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kLimitAddressSpace = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kLimitAddressSpace = false;
#else
constexpr bool kLimitAddressSpace = true;
#endif
#else
constexpr bool kLimitAddressSpace = true;
#endif

// Runs argv[0] (searched on PATH) with stdout and stderr into `log_path`,
// under an address-space and CPU-time limit set in the child, and kills it
// when it has not ended `limits.seconds` after it started. A pipe that
// closes on exec tells a failed exec (its errno) from a program that ran.
Child run_limited(std::vector<char*>& argv, const std::string& log_path, const NqcLimits& limits) {
  Child child;
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) return child;
  int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (log < 0) {
    ::close(report[0]);
    ::close(report[1]);
    return child;
  }
  const rlim_t memory = static_cast<rlim_t>(limits.memory_mib) << 20;
  const rlim_t cpu = static_cast<rlim_t>(limits.seconds);
  pid_t pid = ::fork();
  if (pid == 0) {
    // Only async-signal-safe calls between fork and exec.
    struct rlimit as{memory, memory}, cpu_limit{cpu, cpu + 1};
    if (kLimitAddressSpace) ::setrlimit(RLIMIT_AS, &as);
    ::setrlimit(RLIMIT_CPU, &cpu_limit);
    ::signal(SIGPIPE, SIG_DFL);  // rcxc ignores it; an ignored signal stays ignored across exec
    ::dup2(log, 1);
    ::dup2(log, 2);
    ::execvp(argv[0], argv.data());
    int e = errno;
    [[maybe_unused]] auto n = ::write(report[1], &e, sizeof e);
    ::_exit(127);
  }
  ::close(log);
  ::close(report[1]);
  if (pid < 0) {
    ::close(report[0]);
    return child;
  }
  int exec_errno = 0;
  ssize_t n = 0;
  do n = ::read(report[0], &exec_errno, sizeof exec_errno);
  while (n < 0 && errno == EINTR);
  ::close(report[0]);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(limits.seconds);
  for (;;) {
    pid_t done = ::waitpid(pid, &child.status, WNOHANG);
    if (done == pid || (done < 0 && errno != EINTR)) break;
    if (std::chrono::steady_clock::now() >= deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &child.status, 0);
      child.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  child.started = n != static_cast<ssize_t>(sizeof exec_errno);
  return child;
}

}  // namespace

ExternalCompile compile_with_nqc(const std::string& nqc, const std::string& file,
                                 const std::vector<std::string>& args, const NqcLimits& limits) {
  ExternalCompile result;
  std::string dir = (std::filesystem::temp_directory_path() / "rcxc-nqc-XXXXXX").string();
  if (!mkdtemp(dir.data())) {
    result.failure = "cannot create a temporary folder";
    return result;
  }
  std::string image_path = dir + "/out.rcx", log_path = dir + "/log.txt";
  std::string out_arg = "-O" + image_path;
  // nqc searches includes from the current folder; rcxc from the including
  // file's folder first. -I gives nqc the same start.
  std::string dir_arg = "-I" + (std::filesystem::path(file).parent_path().empty()
                                    ? std::string(".")
                                    : std::filesystem::path(file).parent_path().string());
  std::vector<char*> argv{const_cast<char*>(nqc.c_str()), const_cast<char*>("-Trcx"), dir_arg.data(), out_arg.data()};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(const_cast<char*>(file.c_str()));
  argv.push_back(nullptr);
  Child child = run_limited(argv, log_path, limits);
  auto [log, log_cut] = slurp(log_path);
  const int status = child.status;
  if (!child.started) {
    result.failure = "cannot run '" + nqc + "' (is nqc installed?)";
  } else if (child.timed_out) {
    result.failure = fmt::format("nqc did not finish within {} s and was stopped", limits.seconds);
  } else if (WIFSIGNALED(status)) {
    result.failure = fmt::format("nqc was killed by signal {} (over its limit of {} MiB of memory or {} s?)",
                                 WTERMSIG(status), limits.memory_mib, limits.seconds);
  } else {
    result.messages = parse_nqc_messages(log);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      auto image = rcx::read_image_file(image_path);
      if (auto* img = std::get_if<rcx::Image>(&image)) result.image = std::move(*img);
      else result.failure = "nqc wrote an unreadable image: " + std::get<rcx::ImageError>(image).message;
    } else if (result.messages.empty()) {
      // Nothing nqc said can be shown as its messages: say what ran and how it ended.
      result.failure = fmt::format("nqc failed with exit status {} and {} (the command was: {})",
                                   WEXITSTATUS(status), log.empty() ? "printed nothing" : "printed no message in nqc's form",
                                   shown_command(argv));
      if (!log.empty()) result.failure += "; it printed:\n" + shown_log(log);
      // The end of what is shown is not the end of what it printed.
      if (log_cut) result.failure += fmt::format("\n[... cut: nqc printed more than {} KiB]", kLogBytes / 1024);
    }
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return result;
}

}  // namespace rcx::semtest
