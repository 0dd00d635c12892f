#include <iostream>

#include "cli/commands.h"

namespace rcxc::cli {

void register_compile(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("compile", "Compile an NQC program to an .rcx image");
  auto file = std::make_shared<std::string>();
  cmd->add_option("FILE", *file, "NQC source file")->required();
  cmd->callback([&exit_code, file] {
    std::cerr << "rcxc compile: the compiler is not part of this build yet\n";
    exit_code = kExitFailure;
  });
}

}  // namespace rcxc::cli
