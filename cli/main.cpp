// rcxc: the command-line front of the compiler, emulator and IR link
// libraries. It only parses options and calls the libraries.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/allocator.h"
#include "cli/commands.h"
#include "cli/large_stack.h"
#include "cli/nqc_mode.h"
#include "cli/usage_hint.h"
#include "cli/version.h"

namespace {

// How many words before nqc's own options when the command line is nqc's
// (rcxc linked as `nqc`: 1; `rcxc nqc`: 2), else 0.
int nqc_command_words(int argc, char** argv) {
  if (argc > 0 && rcxc::cli::started_as_nqc(argv[0])) return 1;
  if (argc > 1 && std::string_view(argv[1]) == "nqc") return 2;
  return 0;
}

int run_main(int argc, char** argv) {
  // nqc's command line has its own grammar (-Trcx, -O<file>, actions after
  // the file), so it is read by hand, not by CLI11.
  if (int words = nqc_command_words(argc, argv)) return rcxc::cli::run_nqc_mode({argv + words, argv + argc});

  CLI::App app{"rcxc — NQC compiler and RCX emulator", "rcxc"};
  app.set_version_flag("--version", std::string("rcxc ") + rcxc::kVersion);
  app.require_subcommand(0, 1);
  app.fallthrough(false);
  app.footer(
      "nqc's command line: rcxc nqc [nqc options] FILE, or rcxc installed as 'nqc' (a symbolic link),\n"
      "takes nqc 3.1's options with nqc's meanings (-Trcx, -O<file>, -E<file>, -L, -d, -run, ...; docs/nqc.md).\n"
      "The subcommands' own options differ from nqc's: 'compile -O' sets the optimisation level (-o names\n"
      "the output) and 'compile -E' prints the preprocessed source (errors go to stderr).");

  // In the order `rcxc --help` lists them. Registering every command's
  // options costs about as much CPU as compiling a short program, so a
  // command line that starts with a command's name registers that command
  // alone; anything else (help, version, --help, a typo) registers all.
  struct Command {
    std::string_view name;
    void (*add)(CLI::App&, int&);
  };
  static constexpr Command kCommands[] = {
      {"compile", rcxc::cli::register_compile}, {"run", rcxc::cli::register_run},
      {"disasm", rcxc::cli::register_disasm},   {"test", rcxc::cli::register_test},
      {"compare", rcxc::cli::register_compare}, {"brick", rcxc::cli::register_brick},
      {"download", rcxc::cli::register_download}, {"remote", rcxc::cli::register_remote},
      {"nxt", rcxc::cli::register_nxt},         {"lsp", rcxc::cli::register_lsp},
      {"debug", rcxc::cli::register_debug},     {"format", rcxc::cli::register_format},
  };
  int exit_code = rcxc::cli::kExitOk;
  const Command* named = nullptr;
  for (const Command& c : kCommands)
    if (argc > 1 && c.name == argv[1]) named = &c;
  if (named) {
    named->add(app, exit_code);
  } else {
    for (const Command& c : kCommands) c.add(app, exit_code);
    rcxc::cli::register_help(app, exit_code);
  }

  rcxc::cli::read_integers_as_decimal(app);
  if (auto bare = rcxc::cli::option_without_value({argv + 1, argv + argc})) {
    std::cerr << "rcxc: " << *bare << "\n";
    rcxc::cli::print_nxt_usage_error_json(app, {argv + 1, argv + argc}, *bare);
    return rcxc::cli::kExitUsage;
  }
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
    const std::vector<std::string> words(argv + 1, argv + argc);
    auto hint = rcxc::cli::misspelling_hint(app, words);
    auto habits = rcxc::cli::nqc_habit_hints(words);
    // CLI11's "A subcommand is required" after an unknown action reads as
    // if none were given: the hint names the word instead. Its "argument
    // was not expected" beside a hint said the same word twice (`run --fro
    // p.nqc`), and for -Etemp.log named "-temp.log", a word nobody typed:
    // it is left out when the hints account for every unexpected word.
    const std::vector<std::string> unexpected = app.remaining(true);
    bool hints_say_all = dynamic_cast<const CLI::ExtrasError*>(&e) && !unexpected.empty() &&
                         std::ranges::all_of(unexpected, [&](const std::string& w) {
                           return (hint && rcxc::cli::hint_explains(*hint, w)) || rcxc::cli::left_of_nqc_habit(w, words);
                         });
    std::vector<std::string> said;
    if (!(hint && rcxc::cli::is_missing_action(e)) && !hints_say_all) {
      said.push_back(rcxc::cli::parse_error_text(e));
      // CLI11's "Could not convert: --x = 1e999" for a value no check of ours saw first.
      if (dynamic_cast<const CLI::ConversionError*>(&e))
        said.back() += ": not a value this option or argument can take (its range is in the help below)";
    }
    if (hint) said.push_back(hint->text);
    said.insert(said.end(), habits.begin(), habits.end());
    for (const std::string& line : said) std::cerr << "rcxc: " << line << "\n";
    std::string joined;
    for (const std::string& line : said) joined += (joined.empty() ? "" : "; ") + line;
    rcxc::cli::print_nxt_usage_error_json(app, words, joined);
    const CLI::App* where = &app;
    for (const CLI::App* sub : app.get_subcommands()) where = sub;
    // An unknown action: its name and the other actions' names, as `rcxc
    // remote` answers one, rather than the command's whole help.
    const CLI::App* deepest = &app;
    for (bool deeper = true; deeper;) {
      deeper = false;
      for (const CLI::App* sub : deepest->get_subcommands()) {
        deepest = sub;
        deeper = true;
      }
    }
    if (hint && hint->command && deepest != &app) {
      std::cerr << rcxc::cli::action_list(*deepest);
      return rcxc::cli::kExitUsage;
    }
    // "Usage: rcxc run ...", as `rcxc help run` shows it, not "Usage: run".
    std::cerr << "\n" << where->help(where == &app ? "" : app.get_name());
    return rcxc::cli::kExitUsage;
  }
  if (app.get_subcommands().empty()) {
    std::cerr << "rcxc: a subcommand is required\n\n" << app.help();
    return rcxc::cli::kExitUsage;
  }
  return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) a write then fails with EFBIG, which
  // every output reports, and the temporary it went to is removed; the
  // signal's default would kill rcxc there and leave the temporary behind.
  std::signal(SIGXFSZ, SIG_IGN);
  // A reader that goes away (`rcxc compile f.nqc -o - | head -c1`) killed
  // rcxc without a word (exit 141) when a write came after it left, or let
  // it end 1 with the message below when the write came at the end: the
  // write now fails with EPIPE, and the command says so as for a full disk.
  std::signal(SIGPIPE, SIG_IGN);
  int exit_code = rcxc::cli::kExitFailure;
  if (rcxc::cli::compiles_once(argc, argv)) rcxc::cli::tune_allocator_for_one_compile();
  if (rcxc::cli::let_main_stack_grow_to(rcxc::cli::kWorkStackBytes))
    exit_code = run_main(argc, argv);
  else
    rcxc::cli::run_with_stack(rcxc::cli::kWorkStackBytes, [&] { exit_code = run_main(argc, argv); });
  // What a command printed must have arrived: a listing, a report or an
  // image sent to a full disk is a failure, not a success with nothing in
  // the file.
  bool written = static_cast<bool>(std::cout.flush()) && std::fflush(stdout) == 0 && !std::ferror(stdout);
  if (!written && exit_code == rcxc::cli::kExitOk) {
    std::cerr << "rcxc: cannot write the standard output: what it printed is incomplete\n";
    // nqc mode keeps nqc's codes (docs/nqc.md), where 1 means nothing: 243,
    // as for an -R file that cannot take the text.
    exit_code = nqc_command_words(argc, argv) > 0 ? rcxc::cli::kNqcExitCompile : rcxc::cli::kExitFailure;
  }
  return exit_code;
}
