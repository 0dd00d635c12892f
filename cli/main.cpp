// rcxc: the command-line front of the compiler, emulator and IR link
// libraries. It only parses options and calls the libraries.
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "cli/version.h"

int main(int argc, char** argv) {
  CLI::App app{"rcxc — NQC compiler and RCX emulator", "rcxc"};
  app.set_version_flag("--version", std::string("rcxc ") + rcxc::kVersion);
  app.require_subcommand(0, 1);
  app.fallthrough(false);

  int exit_code = rcxc::cli::kExitOk;
  rcxc::cli::register_compile(app, exit_code);
  rcxc::cli::register_run(app, exit_code);
  rcxc::cli::register_disasm(app, exit_code);
  rcxc::cli::register_test(app, exit_code);
  rcxc::cli::register_compare(app, exit_code);
  rcxc::cli::register_brick(app, exit_code);
  rcxc::cli::register_download(app, exit_code);
  rcxc::cli::register_remote(app, exit_code);
  rcxc::cli::register_lsp(app, exit_code);
  rcxc::cli::register_help(app, exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Bad command line: say what was wrong, then how to call us, on stderr.
    std::cerr << "rcxc: " << e.what() << "\n\n";
    const CLI::App* where = &app;
    for (const CLI::App* sub : app.get_subcommands()) where = sub;
    std::cerr << where->help();
    return rcxc::cli::kExitUsage;
  }
  if (app.get_subcommands().empty()) {
    std::cerr << "rcxc: a subcommand is required\n\n" << app.help();
    return rcxc::cli::kExitUsage;
  }
  return exit_code;
}
