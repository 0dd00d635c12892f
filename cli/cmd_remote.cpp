// `rcxc remote ACTION`: one-shot actions on a brick over the IR link.
#include <unistd.h>

#include <algorithm>
#include <iostream>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/program_loader.h"
#include "cli/tower.h"
#include "frontend/spelling.h"
#include "link/remote.h"
#include "link/transport.h"

namespace rcxc::cli {
namespace {

struct RemoteArgs {
  std::vector<std::string> words;
  std::optional<std::string> port;
  bool csv = false;
  int retries = 5;
};

int exit_code_for(rcx::RemoteFailure kind) {
  switch (kind) {
    case rcx::RemoteFailure::Usage: return kExitUsage;
    case rcx::RemoteFailure::Input: return kExitFailure;
    case rcx::RemoteFailure::Link: return kExitNoReply;
    case rcx::RemoteFailure::Refused: return kExitFailure;
  }
  return kExitFailure;
}

// "unknown action 'alve': did you mean 'alive'?", as rcxc's other commands
// answer a misspelt word; nullopt when the first word is an action.
std::optional<std::string> unknown_action_hint(const std::vector<std::string>& words) {
  if (words.empty()) return std::nullopt;
  std::vector<std::string> names;
  for (const rcx::RemoteAction& action : rcx::remote_actions()) names.emplace_back(action.name);
  if (std::ranges::find(names, words.front()) != names.end()) return std::nullopt;
  std::string said = "unknown action '" + words.front() + "'";
  if (auto near = frontend::closest_name(words.front(), names)) return said + ": did you mean '" + *near + "'?";
  return said + ": the actions are listed below";
}

int run_remote(const RemoteArgs& a) {
  // Before check_remote, which reads the firmware file to judge it: /dev/null
  // read as an empty file said "no data records", and a pipe would be read
  // there and found empty by the real download.
  if (a.words.size() == 2 && a.words[0] == "firmware")
    if (auto problem = special_file_problem(a.words[1], Takes::Files, "give a firmware file of S-records (.srec)")) {
      std::cerr << "rcxc remote: " << *problem << "\n";
      return kExitFailure;
    }
  if (auto bad = rcx::check_remote(a.words)) {
    if (auto hint = unknown_action_hint(a.words)) {
      std::cerr << "rcxc remote: " << *hint << "\n" << rcx::remote_actions_help();
      return kExitUsage;
    }
    std::cerr << "rcxc remote: " << bad->message << "\n";
    return exit_code_for(bad->kind);
  }
  if (a.csv && a.words.front() != "datalog") {
    std::cerr << "rcxc remote: --csv is for datalog, not " << a.words.front() << "\n";
    return kExitUsage;
  }
  auto tower = open_tower("remote", a.port);
  if (!tower) return kExitNoPort;
  auto& port = *tower;
  rcx::LinkOptions link_options;
  link_options.retries = a.retries;
  rcx::Link link = rcx::make_link(port, link_options);
  rcx::RemoteOptions options;
  options.csv = a.csv;
  if (::isatty(STDERR_FILENO))
    options.progress = [](std::size_t done, std::size_t total) {
      std::cerr << fmt::format("\rfirmware {}/{} bytes", done, total) << (done == total ? "\n" : "") << std::flush;
    };
  auto result = rcx::run_remote(link, a.words, options);
  if (auto* e = std::get_if<rcx::RemoteError>(&result)) {
    std::cerr << "rcxc remote: " << e->message << "\n";
    return exit_code_for(e->kind);
  }
  std::cout << std::get<std::string>(result);
  return kExitOk;
}

}  // namespace

void register_remote(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("remote", "Act on an RCX over the IR tower (alive, run, get var 3, datalog, ...)");
  auto a = std::make_shared<RemoteArgs>();
  cmd->add_option("ACTION", a->words, "The action and its arguments")->required();
  cmd->add_option("--port", a->port, "Tower device: usb, serial, a path (default: RCX_PORT, else usb)")->check(not_empty());
  cmd->add_flag("--csv", a->csv, "datalog: print CSV");
  cmd->add_option("--retries", a->retries, "Retries per request (default 5)")->check(in_range(0, 100));
  cmd->footer(rcx::remote_actions_help() +
              "Exit codes: 0 done; 1 bad file or the RCX refused; 2 bad command line or action;\n"
              "3 the port could not be opened; 4 the RCX did not answer.");
  cmd->callback([&exit_code, a] { exit_code = run_remote(*a); });
}

}  // namespace rcxc::cli
