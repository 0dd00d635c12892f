#include "tests/support/process.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcxc::test {

ProcessResult run_process(const std::vector<std::string>& argv, const std::string& stdin_text, int timeout_ms,
                          std::size_t address_space_bytes) {
  int in[2], out[2], err[2];
  if (pipe(in) || pipe(out) || pipe(err)) throw std::runtime_error("pipe failed");
  // A program that exits without reading all of its input (one that
  // refuses it at once) must not kill the test with SIGPIPE: the write
  // below then fails with EPIPE and the input is closed.
  std::signal(SIGPIPE, SIG_IGN);
  pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    std::signal(SIGPIPE, SIG_DFL);  // an ignored signal would stay ignored across exec
    dup2(in[0], 0);
    dup2(out[1], 1);
    dup2(err[1], 2);
    for (int fd : {in[0], in[1], out[0], out[1], err[0], err[1]}) close(fd);
    if (address_space_bytes > 0) {
      rlimit limit{address_space_bytes, address_space_bytes};
      if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(126);
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  close(in[0]);
  close(out[1]);
  close(err[1]);
  ProcessResult r;
  std::size_t written = 0;
  if (stdin_text.empty()) close(in[1]);
  else fcntl(in[1], F_SETFL, O_NONBLOCK);
  bool in_open = !stdin_text.empty();
  bool out_open = true, err_open = true;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (out_open || err_open) {
    int wait_ms = -1;
    if (timeout_ms > 0) {
      auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) {
        // Its output may be held open by its own children too: stop reading.
        kill(pid, SIGKILL);
        r.timed_out = true;
        break;
      }
      wait_ms = static_cast<int>(left.count());
    }
    pollfd fds[3] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}, {in_open ? in[1] : -1, POLLOUT, 0}};
    if (poll(fds, 3, wait_ms) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    char buf[4096];
    auto drain = [&](pollfd& p, int fd, std::string& dst, bool& open) {
      if (!open || !(p.revents & (POLLIN | POLLHUP))) return;
      ssize_t n = read(fd, buf, sizeof buf);
      if (n <= 0) open = false;
      else dst.append(buf, static_cast<std::size_t>(n));
    };
    drain(fds[0], out[0], r.out, out_open);
    drain(fds[1], err[0], r.err, err_open);
    if (in_open && (fds[2].revents & (POLLOUT | POLLERR))) {
      ssize_t n = write(in[1], stdin_text.data() + written, stdin_text.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
      if (n < 0 || written == stdin_text.size()) {
        close(in[1]);
        in_open = false;
      }
    }
  }
  if (in_open) close(in[1]);
  close(out[0]);
  close(err[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  r.max_rss_kb = usage.ru_maxrss;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

ProcessResult run_rcxc(const std::vector<std::string>& args, const std::string& stdin_text, int timeout_ms,
                       std::size_t address_space_bytes) {
  std::vector<std::string> argv{RCXC_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_process(argv, stdin_text, timeout_ms, address_space_bytes);
}

bool built_with_asan() {
#if defined(__SANITIZE_ADDRESS__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return true;
#else
  return false;
#endif
#else
  return false;
#endif
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> nqc_programs_under(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".nqc") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

std::string find_nqc() {
  auto r = run_process({"/bin/sh", "-c", "command -v nqc"});
  return r.exit_code == 0 ? r.out.substr(0, r.out.find('\n')) : std::string();
}

std::string make_temp_dir() {
  const char* base = std::getenv("TMPDIR");
  std::string tmpl = std::string(base ? base : "/tmp") + "/rcxc-test-XXXXXX";
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
  return tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path, ec);
}

std::string TempDir::write(const std::string& name, const std::string& text) const {
  std::string p = path + "/" + name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string TempDir::write(const std::string& name, const std::vector<std::uint8_t>& bytes) const {
  return write(name, std::string(bytes.begin(), bytes.end()));
}

std::vector<std::uint8_t> TempDir::read(const std::string& name) const {
  std::ifstream in(path + "/" + name, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  std::string t = s.str();
  return {t.begin(), t.end()};
}

PtyServer::PtyServer(std::vector<std::string> args, const std::vector<std::string>& extra,
                     const std::string& stderr_path) {
  int p[2];
  if (::pipe(p) != 0) return;
  args.insert(args.begin(), RCXC_BINARY);
  args.insert(args.end(), extra.begin(), extra.end());
  pid = ::fork();
  if (pid == 0) {
    ::dup2(p[1], 1);
    ::close(p[0]);
    ::close(p[1]);
    if (!stderr_path.empty()) {
      int err = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (err >= 0) ::dup2(err, 2);
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(p[1]);
  out = p[0];
  char c;
  pollfd fd{out, POLLIN, 0};
  while (::poll(&fd, 1, 10000) > 0 && ::read(out, &c, 1) == 1 && c != '\n') path += c;
}

int PtyServer::stop() {
  if (pid > 0) {
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    pid = -1;
  }
  if (out >= 0) ::close(out);
  out = -1;
  return exit_code;
}

double cpu_seconds_for(const std::function<void()>& f) {
  auto now = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) / 1e9;
  };
  double start = now();
  f();
  return now() - start;
}

}  // namespace rcxc::test
