// `rcxc help [COMMAND [ACTION...]]` and `rcxc version`: the same text as
// --help and --version, as commands, for people who type them that way.
#include <iostream>

#include "cli/commands.h"
#include "cli/nqc_mode.h"
#include "cli/version.h"

namespace rcxc::cli {

namespace {

// The names of `app`'s commands, "a, b, c", for a message.
std::string command_names(const CLI::App& app, std::string names) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

const CLI::App* find_command(const CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->get_name() == name) return sub;
  return nullptr;
}

}  // namespace

void register_help(CLI::App& app, int& exit_code) {
  auto* help =
      app.add_subcommand("help", "Show the usage of rcxc or of one command (rcxc help compile, rcxc help nxt brick)");
  auto words = std::make_shared<std::vector<std::string>>();
  help->add_option("COMMAND", *words, "The command to describe, and its action for nxt (nxt brick, nxt mailbox write)");
  help->callback([&app, &exit_code, words] {
    if (words->empty()) {
      // app.help() would describe the command being run, `help` itself.
      std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
      exit_code = kExitOk;
      return;
    }
    // `rcxc nqc` is read by hand (nqc's grammar), not registered with CLI11.
    if (words->front() == "nqc") {
      if (words->size() == 1) {
        exit_code = run_nqc_mode({"-help"});
        return;
      }
      std::cerr << "rcxc help: 'rcxc nqc' has no actions; 'rcxc help nqc' describes it\n";
      exit_code = kExitUsage;
      return;
    }
    // `rcxc help nxt brick` as `rcxc nxt brick --help`: the NXT's actions are
    // commands of their own, and `rcxc help nxt brick` was refused as a typo.
    const CLI::App* command = &app;
    std::string path;
    for (const std::string& word : *words) {
      const CLI::App* sub = find_command(*command, word);
      if (!sub) {
        if (command == &app)
          std::cerr << "rcxc help: there is no command '" << word << "' (commands: " << command_names(app, "nqc")
                    << ")\n";
        else if (command_names(*command, "").empty())
          std::cerr << "rcxc help: 'rcxc " << path << "' has no actions; 'rcxc help " << path << "' describes it\n";
        else
          std::cerr << "rcxc help: 'rcxc " << path << "' has no action '" << word
                    << "' (actions: " << command_names(*command, "") << ")\n";
        exit_code = kExitUsage;
        return;
      }
      command = sub;
      path += (path.empty() ? "" : " ") + word;
    }
    // "Usage: rcxc nxt brick", as `rcxc nxt brick --help` shows it.
    std::string prefix = app.get_name();
    for (std::size_t i = 0; i + 1 < words->size(); ++i) prefix += " " + (*words)[i];
    std::cout << command->help(prefix);
    exit_code = kExitOk;
  });

  auto* version = app.add_subcommand("version", "Print rcxc's version");
  version->callback([&exit_code] {
    std::cout << "rcxc " << kVersion << "\n";
    exit_code = kExitOk;
  });
}

}  // namespace rcxc::cli
