// `rcxc brick --pty`: the virtual brick on a pseudo-terminal, for nqc, rcxc
// and any other tool that talks to a serial IR tower.
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <iostream>

#include "cli/commands.h"
#include "link/brick_server.h"

namespace rcxc::cli {
namespace {

struct BrickArgs {
  bool pty = false;
  double noise = 0.0;
  std::uint64_t seed = 1;
  bool fast = false;
  bool no_echo = false;
  bool verbose = false;
};

// SIGINT/SIGTERM become a readable descriptor the server polls, so stopping
// needs no global flag.
int stop_descriptor() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return -1;
  return signalfd(-1, &set, SFD_CLOEXEC);
}

int run_brick(const BrickArgs& a) {
  if (!a.pty) {
    std::cerr << "rcxc brick: only --pty is supported (the brick serves on a pseudo-terminal)\n";
    return kExitUsage;
  }
  if (!(a.noise >= 0.0 && a.noise <= 1.0)) {  // also refuses "nan"
    std::cerr << "rcxc brick: --noise must be a probability 0..1\n";
    return kExitUsage;
  }
  auto opened = rcx::open_pty();
  if (auto* e = std::get_if<rcx::TransportError>(&opened)) {
    std::cerr << "rcxc brick: " << e->message << "\n";
    return kExitFailure;
  }
  auto& pty = std::get<rcx::Pty>(opened);
  int stop = stop_descriptor();
  if (stop < 0) {
    std::cerr << "rcxc brick: cannot watch for signals\n";
    return kExitFailure;
  }
  std::cout << pty.slave_path << std::endl;
  std::cerr << "rcxc brick: serving on " << pty.slave_path << (a.fast ? "" : " at 2400 baud")
            << (a.noise > 0 ? " with noise" : "") << "; Ctrl-C stops\n";
  rcx::Brick brick = rcx::make_brick();
  brick.trace = a.verbose;
  rcx::ServeOptions options;
  options.echo = !a.no_echo;
  options.pace = !a.fast;
  options.noise = a.noise;
  options.seed = a.seed;
  options.stop_fd = stop;
  if (a.verbose) options.on_log = [](const std::string& line) { std::cerr << "brick: " << line << "\n"; };
  auto err = rcx::serve(brick, *pty.master, options);
  ::close(stop);
  rcx::close_pty(pty);
  std::cerr << "rcxc brick: " << brick.counters.requests << " requests, " << brick.counters.replies << " replies, "
            << brick.counters.duplicates << " retransmissions, " << brick.counters.rejected << " rejected\n";
  if (err) {
    std::cerr << "rcxc brick: " << err->message << "\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

void register_brick(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("brick", "Run a virtual RCX that speaks the IR protocol on a pseudo-terminal");
  auto a = std::make_shared<BrickArgs>();
  cmd->add_flag("--pty", a->pty, "Serve on a new pseudo-terminal; its path is printed as the first line");
  // The check also refuses an empty value, which would otherwise read as 0,
  // and NaN, which a plain range check lets through.
  cmd->add_option("--noise", a->noise, "Lose or corrupt each byte with this probability (0..1)")
      ->check(number_in(0.0, 1.0, "0..1"));
  cmd->add_option("--seed", a->seed, "Seed of the noise (default 1)")->check(whole_number());
  cmd->add_flag("--fast", a->fast, "Answer at full speed instead of 2400 baud");
  cmd->add_flag("--no-echo", a->no_echo, "Do not echo (behave like a USB tower)");
  cmd->add_flag("-v,--verbose", a->verbose,
                "Log every request, reply and broadcast, and why requests were rejected or not answered");
  cmd->callback([&exit_code, a] { exit_code = run_brick(*a); });
}

}  // namespace rcxc::cli
