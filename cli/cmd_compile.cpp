// `rcxc compile`: runs the frontend (preprocessor, parser, checks) on an NQC
// file and reports its diagnostics; with -E prints the preprocessed text.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <iostream>
#include <memory>
#include <optional>

#include "cli/color.h"
#include "cli/commands.h"
#include "savefile/savefile.h"
#include "cli/program_loader.h"
#include "backend/listing.h"
#include "frontend/frontend.h"
#include "rcx/image.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace rcxc::cli {
namespace {

struct CompileArgs {
  std::string file;
  std::optional<std::string> output;
  CompilerArgs compiler;                   // -I -D -U -n -O
  std::vector<std::string> warning_flags;  // -Werror, -Wno-NAME, ... in order
  std::string diagnostics = "text";
  std::string color = "auto";
  std::size_t max_errors = kDefaultMaxErrors;
  bool preprocess_only = false;
  bool no_warnings = false;
  std::string listing;  // "-" = standard output
  bool verbose = false;
};

void print_diagnostics(const Diagnostics& diags, const SourceManager& sm, const CompileArgs& a) {
  std::cerr << render_all(diags, sm, RenderOptions{a.diagnostics == "json", a.max_errors, color_on_stderr(a.color)});
}

// FILE.nqc -> FILE.rcx unless -o says otherwise.
std::string image_path(const CompileArgs& a) {
  if (a.output) return *a.output;
  std::string base = a.file;
  auto dot = base.find_last_of('.');
  if (dot != std::string::npos && base.find('/', dot) == std::string::npos) base.resize(dot);
  return base + ".rcx";
}

// The source file (or an included one) that `path` names, if any: writing
// there would destroy the program.
std::optional<std::string> source_file_at(const std::string& path, const SourceManager& sm) {
  for (std::uint32_t f = 0; f < sm.size(); ++f) {
    std::error_code ec;
    if (std::filesystem::equivalent(path, sm.path(f), ec) && !ec) return sm.path(f);
  }
  return std::nullopt;
}

// Says so when `target` is the program or a file it includes.
bool overwrites_source(const std::string& target, const SourceManager& sm) {
  auto source = source_file_at(target, sm);
  if (source)
    std::cerr << "rcxc compile: refusing to write " << target << ": it is the source file " << *source
              << " (choose another name)\n";
  return source.has_value();
}

int write_outputs(const CompileArgs& a, const backend::Output& out, const SourceManager& sm) {
  auto image = rcx::write_image(out.image);
  std::string path = image_path(a);  // "-": the standard output
  if (!a.listing.empty() && a.listing != "-" && path != "-" && savefile::same_file(path, a.listing)) {
    std::cerr << "rcxc compile: the image and the listing would both be written to " << a.listing
              << " (choose another name)\n";
    return kExitUsage;
  }
  for (const std::string* target : {static_cast<const std::string*>(&path), &a.listing}) {
    if (target->empty() || *target == "-") continue;
    if (overwrites_source(*target, sm)) return kExitUsage;
  }
  // A listing file before the image: one that cannot be written (a full
  // disk, a missing folder) failed the command after a fresh image was in
  // place, which `make` then took for built. The image is the output a
  // build waits for, so it is written last, only when all else went well.
  if (!a.listing.empty() && a.listing != "-")
    if (auto unwritten = savefile::write_file_atomically(a.listing, backend::listing(out, &sm))) {
      std::cerr << "rcxc compile: cannot write " << a.listing << ": " << *unwritten << "\n";
      return kExitFailure;
    }
  if (path == "-") {
    // For a pipe; bad_arguments has made sure the listing goes elsewhere.
    std::cout.write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
    if (!std::cout.flush()) {
      std::cerr << "rcxc compile: cannot write the image to the standard output\n";
      return kExitFailure;
    }
  } else if (auto unwritten = savefile::write_file_atomically(path, std::string(image.begin(), image.end()))) {
    std::cerr << "rcxc compile: cannot write " << path << ": " << *unwritten << "\n";
    return kExitFailure;
  }
  if (a.listing == "-") std::cout << backend::listing(out, &sm);
  return kExitOk;
}

// -E's text goes where -o says, as gcc's does; the standard output without it.
int write_preprocessed(const CompileArgs& a, const std::string& text, const SourceManager& sm) {
  if (!a.output || *a.output == "-") {
    std::cout << text;
    return kExitOk;
  }
  if (overwrites_source(*a.output, sm)) return kExitUsage;
  if (auto unwritten = savefile::write_file_atomically(*a.output, text)) {
    std::cerr << "rcxc compile: cannot write " << *a.output << ": " << *unwritten << "\n";
    return kExitFailure;
  }
  return kExitOk;
}

// "-" when the standard output is a terminal, or a path to one (-o /dev/tty,
// -o /dev/stdout on a terminal).
bool names_a_terminal(const std::string& path) {
  if (path == "-") return ::isatty(STDOUT_FILENO) != 0;
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) return false;
  int fd = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) return false;
  bool tty = ::isatty(fd) != 0;
  ::close(fd);
  return tty;
}

// Command-line values the option parser cannot judge: macro names and an
// empty output name.
std::optional<std::string> bad_arguments(const CompileArgs& a) {
  if (auto bad = bad_compiler_arguments(a.compiler)) return bad;
  if (a.output && a.output->empty()) return "-o needs a file name";
  if (a.preprocess_only && !a.listing.empty())
    return "-E prints the preprocessed source and stops: there is no code to list (leave out --listing)";
  if (a.preprocess_only) return std::nullopt;
  // FILE.rcx is named after FILE; the standard input has no name to give.
  if (a.file == frontend::kStandardInput && !a.output)
    return "the program comes from the standard input: name the image with -o FILE (-o - writes it to the standard "
           "output)";
  if (a.output == "-" && a.listing == "-")
    return "the image (-o -) and the listing (--listing) would both go to the standard output: write one of them "
           "to a file (--listing=FILE)";
  // The image's bytes on a terminal are garbage at best, and an escape
  // sequence among them is acted on (ESC c resets the terminal).
  if (a.output && names_a_terminal(*a.output))
    return "-o " + *a.output + " would write the binary image to the terminal: send the standard output to a file "
           "or a pipe, or name the image with -o FILE";
  return std::nullopt;
}

int run_compile(const CompileArgs& a) {
  if (auto bad = bad_arguments(a)) {
    std::cerr << "rcxc compile: " << *bad << "\n";
    return kExitUsage;
  }
  if (auto problem = special_file_problem(a.file, Takes::Files, "give an NQC source file, or '-' for the standard input")) {
    std::cerr << "rcxc compile: " << *problem << "\n";
    return kExitFailure;
  }
  SourceManager sm;
  Diagnostics diags;
  for (const auto& w : a.warning_flags) {
    if (auto bad = apply_warning_option(diags.policy, w)) {
      std::cerr << "rcxc compile: " << *bad << "\n";
      return kExitUsage;
    }
  }
  diags.policy.none = a.no_warnings;
  const CompileRequest request = compile_request(a.compiler);
  if (a.preprocess_only) {
    auto text = frontend::preprocess_file(a.file, request.frontend, sm, diags);
    print_diagnostics(diags, sm, a);
    if (!text) return kExitFailure;
    return write_preprocessed(a, *text, sm);
  }
  CompileResult compiled = compile_file(a.file, request, std::move(diags));
  print_diagnostics(compiled.diagnostics, compiled.sources, a);
  if (a.verbose)
    for (const auto& line : compiled.log) std::cerr << "rcxc: " << line << "\n";
  if (!compiled.output) return kExitFailure;
  return write_outputs(a, *compiled.output, compiled.sources);
}

}  // namespace

// --listing's value is optional, so `--listing prog.nqc` takes the program
// as the listing's name; say so instead of only that FILE is missing.
int missing_source(const CompileArgs& a) {
  const std::string& l = a.listing;
  bool looks_like_source = l.size() > 4 && (l.ends_with(".nqc") || l.ends_with(".nqh"));
  if (looks_like_source)
    std::cerr << "rcxc compile: no source file: --listing took " << l
              << " as the name of the listing to write; write --listing=FILE, or --listing after the source file\n";
  else
    std::cerr << "rcxc compile: no source file: give the NQC program to compile (rcxc compile FILE)\n";
  return kExitUsage;
}

void register_compile(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("compile", "Compile an NQC program to an .rcx image");
  auto args = std::make_shared<CompileArgs>();
  // Not required() for CLI11: a missing FILE is said in the callback, which
  // can tell when `--listing prog.nqc` took the source as its value.
  cmd->add_option("FILE", args->file, "NQC source file (required; - reads the standard input)");
  cmd->add_option("-o,--output", args->output, "Output .rcx image (default: FILE with .rcx; - writes the standard output)");
  add_compiler_options(cmd, args->compiler);
  cmd->add_flag("-E", args->preprocess_only, "Print the preprocessed source (to -o FILE if given) and stop (nqc's -E<file> writes errors; here they go to stderr)");
  add_repeatable(cmd, "-W", args->warning_flags,
                 "-Werror: treat warnings as errors; -Wno-NAME: do not give warning NAME; -Werror=NAME: make it an "
                 "error (-Wno-error=NAME: not even with -Werror); -Wall: every warning (the default). NAME, as "
                 "shown after each warning: " + warning_names_list());
  cmd->add_flag("-w", args->no_warnings, "Do not report warnings");
  auto* listing = cmd->add_option("--listing", args->listing, "Write a listing to FILE (or standard output without =FILE)")
                      ->expected(0, 1)
                      ->default_str("-");
  cmd->add_flag("-v,--verbose", args->verbose, "Report what the optimiser did (inlining, loop counters, sizes)");
  cmd->add_option("--diagnostics", args->diagnostics, "Diagnostics format: text (default) or json")
      ->check(CLI::IsMember({"text", "json"}));
  add_color_option(cmd, args->color);
  cmd->add_option("--max-errors", args->max_errors, "Stop printing after N errors (default 20, 0: print all)")
      ->check(in_range(0, 1000000).description(""));
  cmd->callback([&exit_code, args, listing] {
    // CLI11 runs no check on an empty value of an option whose value is
    // optional: `--listing ''` wrote no listing with exit 0.
    if (listing->count() > 0 && args->listing.empty()) {
      std::cerr << "rcxc: --listing: needs a value, not '' (--listing alone prints the listing)\n";
      exit_code = kExitUsage;
      return;
    }
    if (args->file.empty()) {
      exit_code = missing_source(*args);
      return;
    }
    try {
      exit_code = run_compile(*args);
    } catch (const std::exception& e) {
      // A bug or an exhausted machine; say so rather than abort.
      std::cerr << "rcxc compile: internal error: " << e.what() << "\n";
      exit_code = kExitFailure;
    }
  });
}

}  // namespace rcxc::cli
