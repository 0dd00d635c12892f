// `rcxc disasm FILE`: lists every task and subroutine of an image; NQC
// source is compiled in memory first (with `rcxc compile`'s options).
#include <iostream>
#include <variant>

#include "backend/disasm.h"
#include "cli/commands.h"
#include "cli/program_loader.h"
#include "rcx/image.h"

namespace rcxc::cli {

void register_disasm(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("disasm", "List the bytecode of an .rcx image (or of NQC source, compiled in memory)");
  auto file = std::make_shared<std::string>();
  auto compiler = std::make_shared<CompilerArgs>();
  cmd->add_option("FILE", *file, ".rcx image or NQC source")->required()->check(not_empty());
  add_compiler_options(cmd, *compiler);
  cmd->callback([&exit_code, file, compiler] {
    if (auto bad = bad_compiler_arguments(*compiler)) {
      std::cerr << "rcxc disasm: " << *bad << "\n";
      exit_code = kExitUsage;
      return;
    }
    auto image = load_program(*file, compile_request(*compiler));
    if (auto* e = std::get_if<std::string>(&image)) {
      std::cerr << "rcxc disasm: " << *e << "\n";
      exit_code = kExitFailure;
      return;
    }
    if (auto note = unused_compiler_options(*file, *compiler)) std::cerr << "rcxc disasm: " << *note << "\n";
    std::cout << backend::disassemble(std::get<rcx::Image>(image));
    exit_code = kExitOk;
  });
}

}  // namespace rcxc::cli
