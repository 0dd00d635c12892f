// `rcxc download`: put a program into an RCX program slot over the IR link.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/program_loader.h"
#include "cli/tower.h"
#include "link/download.h"
#include "rcx/image.h"
#include "link/transport.h"

namespace rcxc::cli {
namespace {

struct DownloadArgs {
  std::string file;
  std::optional<std::string> port;
  int program = 1;
  bool run = false;
  int retries = 30;
  bool no_sound = false;
  bool verbose = false;
  CompilerArgs compiler;  // for a source FILE, as `rcxc compile` takes them
};

// "[########............]  120/300 bytes  40%  52 B/s", redrawn in place.
void draw_progress(const rcx::DownloadProgress& p, std::chrono::steady_clock::time_point start) {
  constexpr int kWidth = 24;
  double fraction = p.total ? static_cast<double>(p.done) / static_cast<double>(p.total) : 1.0;
  int filled = static_cast<int>(fraction * kWidth);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double rate = seconds > 0 ? static_cast<double>(p.done) / seconds : 0.0;
  std::cerr << fmt::format("\r[{}{}] {:5}/{} bytes {:3.0f}% {:5.0f} B/s", std::string(static_cast<std::size_t>(filled), '#'),
                           std::string(static_cast<std::size_t>(kWidth - filled), '.'), p.done, p.total,
                           fraction * 100.0, rate)
            << std::flush;
}

int exit_code_for(rcx::DownloadFailure kind) {
  switch (kind) {
    case rcx::DownloadFailure::BadInput: return kExitFailure;
    case rcx::DownloadFailure::NoBrick: return kExitNoReply;
    case rcx::DownloadFailure::LinkFailed: return kExitNoReply;
    case rcx::DownloadFailure::BrickRefused: return kExitFailure;
  }
  return kExitFailure;
}

int run_download(const DownloadArgs& a) {
  if (auto bad = bad_compiler_arguments(a.compiler)) {
    std::cerr << "rcxc download: " << *bad << "\n";
    return kExitUsage;
  }
  auto image = load_program(a.file, compile_request(a.compiler));
  if (auto* e = std::get_if<std::string>(&image)) {
    std::cerr << "rcxc download: " << *e << "\n";
    return kExitFailure;
  }
  if (auto note = unused_compiler_options(a.file, a.compiler)) std::cerr << "rcxc download: " << *note << "\n";
  auto tower = open_tower("download", a.port);
  if (!tower) return kExitNoPort;
  auto& port = *tower;
  rcx::LinkOptions link_options;
  link_options.retries = a.retries;
  rcx::Link link = rcx::make_link(port, link_options);
  if (a.verbose) link.on_rejected = [](const std::string& why) { std::cerr << "\nrejected: " << why << "\n"; };
  rcx::DownloadOptions options;
  options.program = a.program;
  options.run = a.run;
  options.sound = !a.no_sound;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const auto start = std::chrono::steady_clock::now();
  rcx::ProgressFn progress;
  if (tty) progress = [start](const rcx::DownloadProgress& p) { draw_progress(p, start); };
  auto result = rcx::download(link, std::get<rcx::Image>(image), options, progress);
  if (tty) std::cerr << "\n";
  if (auto* e = std::get_if<rcx::DownloadError>(&result)) {
    std::cerr << "rcxc download: " << e->message << "\n";
    return exit_code_for(e->kind);
  }
  const auto& report = std::get<rcx::DownloadReport>(result);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int retransmissions = report.link.attempts - report.link.requests;
  std::cerr << fmt::format("downloaded {} bytes to program {} in {:.1f} s ({} block{}, {} retransmission{}){}\n",
                           report.bytes, a.program, seconds, report.blocks, report.blocks == 1 ? "" : "s",
                           retransmissions, retransmissions == 1 ? "" : "s", a.run ? ", running" : "");
  return kExitOk;
}

}  // namespace

void register_download(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("download", "Compile if needed and download a program into the RCX over the IR tower");
  auto a = std::make_shared<DownloadArgs>();
  cmd->add_option("FILE", a->file, "NQC source (compiled first) or .rcx image")->required()->check(not_empty());
  add_compiler_options(cmd, a->compiler);
  cmd->add_option("--port", a->port, "Tower device: usb, serial, a path (default: RCX_PORT, else usb)")->check(not_empty());
  cmd->add_option("--program", a->program, "Program slot 1..5 (default 1)")->check(in_range(1, 5));
  cmd->add_flag("--run", a->run, "Start the program after downloading");
  cmd->add_option("--retries", a->retries, "Retries per request (default 30)")->check(in_range(0, 100));
  cmd->add_flag("--no-sound", a->no_sound, "Do not play the download-done sound");
  cmd->add_flag("-v,--verbose", a->verbose, "Say why replies were rejected");
  cmd->footer(
      "Exit codes: 0 downloaded and every block acknowledged; 1 bad input (compile errors, a bad image) or the\n"
      "RCX refused it;\n"
      "2 bad command line; 3 the port could not be opened; 4 the RCX did not answer or the link failed.");
  cmd->callback([&exit_code, a] { exit_code = run_download(*a); });
}

}  // namespace rcxc::cli
