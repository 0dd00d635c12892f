// `rcxc format [FILE...]`: lays NQC source out in one style (docs/format.md)
// through format/. Prints the result, rewrites the files (-i), or only
// names the files that are not formatted (--check, for CI).
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <variant>

#include "cli/commands.h"
#include "savefile/savefile.h"
#include "cli/program_loader.h"
#include "format/format.h"
#include "frontend/frontend.h"
#include "rcx/file_read.h"

namespace rcxc::cli {
namespace {

struct FormatArgs {
  std::vector<std::string> files;
  bool in_place = false;
  bool check = false;
  int indent = format::Style{}.indent;
};

enum class Outcome { Unchanged, Changed, Failed };

// Formats one file as the arguments say; problems go to stderr.
Outcome format_one(const std::string& path, const FormatArgs& args) {
  if (auto problem = special_file_problem(path, Takes::Files, "give NQC source files, or '-' for the standard input")) {
    std::cerr << "rcxc format: " << *problem << "\n";
    return Outcome::Failed;
  }
  auto [name, read] = frontend::read_source(path);
  if (auto* problem = std::get_if<rcx::FileProblem>(&read)) {
    if (*problem == rcx::FileProblem::TooLarge)
      std::cerr << "rcxc format: " << rcx::too_large_message(name, rcx::kSourceFile) << "\n";
    else if (*problem == rcx::FileProblem::Directory)
      std::cerr << "rcxc format: " << name << ": is a directory, not a source file\n";
    else if (*problem == rcx::FileProblem::CannotOpen && path != frontend::kStandardInput)
      std::cerr << "rcxc format: " << name << ": cannot open file: " << rcx::cannot_open_reason(path) << "\n";
    else
      std::cerr << "rcxc format: " << name << ": cannot be read\n";
    return Outcome::Failed;
  }
  const std::string& text = std::get<std::string>(read);
  auto formatted = format::format_source(text, {.indent = args.indent});
  if (auto* refusal = std::get_if<format::Refusal>(&formatted)) {
    std::cerr << "rcxc format: " << name << ": " << refusal->message
              << (args.in_place ? "; the file is left as it was\n" : "\n");
    return Outcome::Failed;
  }
  const std::string& out = std::get<std::string>(formatted);
  bool changed = out != text;
  if (args.check) {
    if (changed) std::cout << name << "\n";
  } else if (args.in_place) {
    auto unwritten = changed ? savefile::write_file_atomically(path, out) : std::nullopt;
    if (unwritten) {
      std::cerr << "rcxc format: cannot write " << name << ": " << *unwritten << "; it is left as it was\n";
      return Outcome::Failed;
    }
  } else {
    std::cout << out;
  }
  return changed ? Outcome::Changed : Outcome::Unchanged;
}

}  // namespace

void register_format(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("format", "Lay NQC source out in rcxc's style (docs/format.md); '-' or none: stdin");
  auto args = std::make_shared<FormatArgs>();
  cmd->add_option("FILE", args->files, "NQC source files ('-' for the standard input)")->check(not_empty());
  cmd->add_flag("-i,--in-place", args->in_place, "Rewrite each file that changes (through a temporary file)");
  cmd->add_flag("--check", args->check,
                "Change nothing; list the files that formatting would change, and exit 1 if there are any");
  cmd->add_option("--indent", args->indent, "Spaces per level of nesting (default 2)")
      ->check(in_range(format::kMinIndent, format::kMaxIndent));
  cmd->callback([&exit_code, args] {
    if (args->in_place && args->check) {
      std::cerr << "rcxc format: --in-place and --check do not go together\n";
      exit_code = kExitUsage;
      return;
    }
    std::vector<std::string> files = args->files;
    if (files.empty()) files.emplace_back(frontend::kStandardInput);
    auto stdin_count = std::count(files.begin(), files.end(), std::string(frontend::kStandardInput));
    // Read a second time it is empty: its text would be printed once and
    // then nothing, as if the second were an empty file.
    if (stdin_count > 1) {
      std::cerr << "rcxc format: '-' (the standard input) is given " << stdin_count << " times; it can be read once\n";
      exit_code = kExitUsage;
      return;
    }
    if (args->in_place && stdin_count > 0) {
      std::cerr << "rcxc format: --in-place needs files; the standard input has nowhere to be written back\n";
      exit_code = kExitUsage;
      return;
    }
    bool failed = false;
    bool changed = false;
    for (const std::string& file : files) {
      Outcome o = format_one(file, *args);
      failed = failed || o == Outcome::Failed;
      changed = changed || o == Outcome::Changed;
    }
    exit_code = failed || (args->check && changed) ? kExitFailure : kExitOk;
  });
}

}  // namespace rcxc::cli
