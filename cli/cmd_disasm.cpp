// `rcxc disasm FILE.rcx`: lists every task and subroutine of an image.
#include <iostream>
#include <variant>

#include "backend/disasm.h"
#include "cli/commands.h"
#include "rcx/image.h"

namespace rcxc::cli {

void register_disasm(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("disasm", "List the bytecode of an .rcx image");
  auto file = std::make_shared<std::string>();
  cmd->add_option("FILE", *file, ".rcx image")->required();
  cmd->callback([&exit_code, file] {
    auto image = rcx::read_image_file(*file);
    if (auto* e = std::get_if<rcx::ImageError>(&image)) {
      std::cerr << "rcxc disasm: " << e->message << "\n";
      exit_code = kExitFailure;
      return;
    }
    std::cout << backend::disassemble(std::get<rcx::Image>(image));
    exit_code = kExitOk;
  });
}

}  // namespace rcxc::cli
