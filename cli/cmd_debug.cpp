// `rcxc debug`: the debug adapter on standard input and output
// (docs/editors.md). Everything but the process set-up is in dap/.
#include <iostream>

#include "cli/commands.h"
#include "dap/session.h"

namespace rcxc::cli {

void register_debug(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "debug", "Debug adapter (DAP over standard input and output): step NQC source on the emulator, for editors");
  cmd->callback([&exit_code] {
    std::ios::sync_with_stdio(false);
    dap::Session session;
    exit_code = dap::serve(session, std::cin, std::cout, std::cerr);
  });
}

}  // namespace rcxc::cli
