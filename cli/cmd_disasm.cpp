#include <iostream>

#include "cli/commands.h"

namespace rcxc::cli {

void register_disasm(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("disasm", "List the bytecode of an .rcx image");
  auto file = std::make_shared<std::string>();
  cmd->add_option("FILE", *file, ".rcx image")->required();
  cmd->callback([&exit_code, file] {
    std::cerr << "rcxc disasm: the disassembler is not part of this build yet\n";
    exit_code = kExitFailure;
  });
}

}  // namespace rcxc::cli
