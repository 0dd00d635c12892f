// `rcxc lsp`: the language server on standard input and output
// (docs/editors.md). Everything but the process set-up is in lsp/.
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "cli/program_loader.h"
#include "cli/version.h"
#include "lsp/server.h"

namespace rcxc::cli {

namespace {
struct LspArgs {
  std::vector<std::string> include_dirs;
  std::vector<std::string> defines;
  std::vector<std::string> undefines;
  std::vector<std::string> warning_flags;  // -Wno-NAME, -Werror, ... as rcxc compile takes them
  bool no_stdlib = false;
  bool stdio = false;
  std::string stdlib_dir;
};
}  // namespace

void register_lsp(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("lsp", "Language server (LSP over standard input and output) for editors");
  auto args = std::make_shared<LspArgs>();
  add_repeatable(cmd, "-I", args->include_dirs, "Add a folder to the #include search path");
  add_repeatable(cmd, "-D", args->defines, "Define a macro: -DNAME or -DNAME=VALUE");
  add_repeatable(cmd, "-U", args->undefines, "Undefine a macro");
  add_repeatable(cmd, "-W", args->warning_flags,
                 "Warnings as rcxc compile takes them: -Wno-NAME leaves warning NAME out of the editor's "
                 "diagnostics (also initializationOptions.warnings: [\"no-NAME\", ...])");
  cmd->add_flag("-n", args->no_stdlib, "Do not read the standard library rcx.nqh");
  // Language clients (VS Code's among them) pass --stdio; it is the only transport.
  cmd->add_flag("--stdio", args->stdio, "Talk over standard input and output (the default and only transport)");
  // A file there would make every go to definition into the library answer
  // nothing, with no word on why.
  auto folder_or_new = CLI::Validator(
      [](std::string& dir) {
        std::error_code ec;
        bool file = std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec);
        return file ? dir + " is a file, not a folder" : std::string();
      },
      "", "folder");
  cmd->add_option("--stdlib-dir", args->stdlib_dir,
                  "Where to write the copy of rcx.nqh that go to definition opens (default: a cache folder)")
      ->check(not_empty())
      ->check(folder_or_new);
  cmd->callback([&exit_code, args] {
    // As every compiling command checks them: a bad name here made a server
    // that compiled every document with it, saying nothing.
    if (auto bad = bad_compiler_arguments({.include_dirs = args->include_dirs, .defines = args->defines, .undefines = args->undefines})) {
      std::cerr << "rcxc lsp: " << *bad << "\n";
      exit_code = kExitUsage;
      return;
    }
    lsp::Server server;
    for (const auto& w : args->warning_flags) {
      if (auto bad = apply_warning_option(server.warnings, w)) {
        std::cerr << "rcxc lsp: " << *bad << "\n";
        exit_code = kExitUsage;
        return;
      }
    }
    server.options.include_dirs = args->include_dirs;
    for (const auto& d : args->defines) server.options.define(d);
    server.options.undefines = args->undefines;
    server.options.no_stdlib = args->no_stdlib;
    server.stdlib_dir = args->stdlib_dir;
    server.version = kVersion;
    std::ios::sync_with_stdio(false);
    exit_code = lsp::serve(server, std::cin, std::cout, std::cerr);
  });
}

}  // namespace rcxc::cli
