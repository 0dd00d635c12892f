// `rcxc help [COMMAND]` and `rcxc version`: the same text as --help and
// --version, as commands, for people who type them that way.
#include <iostream>

#include "cli/commands.h"
#include "cli/nqc_mode.h"
#include "cli/version.h"

namespace rcxc::cli {

void register_help(CLI::App& app, int& exit_code) {
  auto* help = app.add_subcommand("help", "Show the usage of rcxc or of one command (rcxc help compile)");
  auto command = std::make_shared<std::string>();
  help->add_option("COMMAND", *command, "The command to describe");
  help->callback([&app, &exit_code, command] {
    if (command->empty()) {
      // app.help() would describe the command being run, `help` itself.
      std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
      exit_code = kExitOk;
      return;
    }
    // `rcxc nqc` is read by hand (nqc's grammar), not registered with CLI11.
    if (*command == "nqc") {
      exit_code = run_nqc_mode({"-help"});
      return;
    }
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == *command) {
        std::cout << sub->help(app.get_name());
        exit_code = kExitOk;
        return;
      }
    std::string names = "nqc";
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      names += ", " + sub->get_name();
    std::cerr << "rcxc help: there is no command '" << *command << "' (commands: " << names << ")\n";
    exit_code = kExitUsage;
  });

  auto* version = app.add_subcommand("version", "Print rcxc's version");
  version->callback([&exit_code] {
    std::cout << "rcxc " << kVersion << "\n";
    exit_code = kExitOk;
  });
}

}  // namespace rcxc::cli
