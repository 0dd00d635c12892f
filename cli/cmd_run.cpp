#include <iostream>

#include "cli/commands.h"

namespace rcxc::cli {

void register_run(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("run", "Run a program on the RCX emulator in virtual time");
  auto file = std::make_shared<std::string>();
  cmd->add_option("FILE", *file, ".rcx image or .nqc source")->required();
  cmd->callback([&exit_code, file] {
    std::cerr << "rcxc run: the emulator is not part of this build yet\n";
    exit_code = kExitFailure;
  });
}

}  // namespace rcxc::cli
