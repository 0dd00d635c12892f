#include "cli/program_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "backend/compile.h"
#include "ir/lower.h"
#include "cli/commands.h"
#include "frontend/parse.h"
#include "rcx/file_read.h"

namespace rcxc::cli {
namespace {

bool is_identifier(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// A keyword as the name: as a #define of it is refused (nqc's lexer takes
// its keywords first, so nqc never expands such a macro; rcxc would, and
// `-D task=1` broke every task).
std::optional<std::string> bad_macro_name(const std::string& option, const std::string& name) {
  if (!is_identifier(name)) return option + ": a macro name must be an identifier";
  if (const char* why = frontend::not_a_macro_name(name))
    return option + ": '" + name + "' cannot be a macro name: it is " +
           (why == std::string_view("a keyword") ? std::string(why) : "reserved by nqc (" + std::string(why) + ")");
  return std::nullopt;
}


ir::OptLevel level_of(const std::string& optimize) {
  return optimize == "0"   ? ir::OptLevel::O0
         : optimize == "1" ? ir::OptLevel::O1
         : optimize == "s" ? ir::OptLevel::Os
                           : ir::OptLevel::O2;
}

}  // namespace

void add_compiler_options(CLI::App* cmd, CompilerArgs& args) {
  add_repeatable(cmd, "-I", args.include_dirs, "Add a folder to the #include search path");
  add_repeatable(cmd, "-D", args.defines, "Define a macro: -DNAME or -DNAME=VALUE");
  add_repeatable(cmd, "-U", args.undefines, "Undefine a macro");
  cmd->add_flag("-n", args.no_stdlib, "Do not read the standard library rcx.nqh");
  cmd->add_option("-O", args.optimize,
                  "Optimisation: -O0 none; -O1 clean-ups only, every motor command kept; -O2 (default) the "
                  "fastest code, shrunk only where no instruction more runs; -Os the smallest code, trading "
                  "time for bytes (outlined code runs a call and a return more). Not nqc's -O<file>: rcxc "
                  "compile's -o names the output")
      ->check(CLI::Validator(
          [](std::string& level) {
            if (level == "0" || level == "1" || level == "2" || level == "s") return std::string();
            // gcc's -O3 or -Ofast: a level that does not exist. A name with a
            // dot or a slash is nqc's -O<file>: say what to write instead.
            if (level.find_first_of("./") == std::string::npos)
              return "-O" + level + ": there is no such optimisation level: -O0, -O1, -O2 (the default, the fastest " +
                     "code) or -Os (the smallest); the output file is -o FILE";
            return "-O" + level + ": -O is the optimisation level here (-O0, -O1, -O2, -Os); the output file is -o " +
                   level + " (nqc's -O<file>; 'rcxc nqc' takes nqc's options)";
          },
          "{0,1,2,s}"));
}

std::optional<std::string> bad_compiler_arguments(const CompilerArgs& args) {
  for (const auto& d : args.defines)
    if (auto bad = bad_macro_name("-D" + d, d.substr(0, d.find('=')))) return bad;
  for (const auto& u : args.undefines)
    if (auto bad = bad_macro_name("-U" + u, u)) return bad;
  return std::nullopt;
}

std::variant<CompilerArgs, std::string> parse_compiler_options(const std::vector<std::string>& words,
                                                               const std::string& base_dir) {
  CLI::App app{"compiler options"};
  CompilerArgs args;
  add_compiler_options(&app, args);
  std::vector<std::string> reversed(words.rbegin(), words.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return std::string(e.what());
  }
  if (auto bad = bad_compiler_arguments(args)) return *bad;
  for (auto& dir : args.include_dirs)
    if (std::filesystem::path(dir).is_relative()) dir = (std::filesystem::path(base_dir) / dir).string();
  return args;
}

std::variant<CompilerArgs, std::string> with_file_options(const CompilerArgs& command_line,
                                                          const std::vector<std::string>& words,
                                                          const std::string& file) {
  if (words.empty()) return command_line;
  auto parsed = parse_compiler_options(words, std::filesystem::path(file).parent_path().string());
  if (auto* error = std::get_if<std::string>(&parsed)) return "bad @options: " + *error;
  const auto& own = std::get<CompilerArgs>(parsed);
  CompilerArgs merged = command_line;
  merged.include_dirs.insert(merged.include_dirs.end(), own.include_dirs.begin(), own.include_dirs.end());
  merged.defines.insert(merged.defines.end(), own.defines.begin(), own.defines.end());
  merged.undefines.insert(merged.undefines.end(), own.undefines.begin(), own.undefines.end());
  merged.no_stdlib = merged.no_stdlib || own.no_stdlib;
  bool picks_level = std::any_of(words.begin(), words.end(), [](const std::string& w) { return w.rfind("-O", 0) == 0; });
  if (picks_level) merged.optimize = own.optimize;
  return merged;
}

std::vector<std::string> nqc_arguments(const CompilerArgs& args) {
  std::vector<std::string> out;
  for (const auto& dir : args.include_dirs) out.push_back("-I" + dir);
  for (const auto& d : args.defines) out.push_back("-D" + d);
  for (const auto& u : args.undefines) out.push_back("-U" + u);
  if (args.no_stdlib) out.push_back("-n");
  return out;
}

CompileRequest compile_request(const CompilerArgs& args) {
  CompileRequest r;
  r.frontend.include_dirs = args.include_dirs;
  for (const auto& d : args.defines) r.frontend.define(d);
  r.frontend.undefines = args.undefines;
  r.frontend.no_stdlib = args.no_stdlib;
  r.level = level_of(args.optimize);
  return r;
}

namespace {

// backend::compile_file's steps after `parse`, keeping the parsed
// program's globals.
template <typename Parse>
CompileResult compile_parsed(Parse parse, const CompileRequest& request, Diagnostics diags) {
  CompileResult r;
  r.diagnostics = std::move(diags);
  std::optional<ir::Program> lowered;
  {
    std::optional<ast::Program> program = parse(r.sources, r.diagnostics);
    if (program) {
      for (const auto& g : program->globals) r.globals.push_back(g.name);
      lowered = ir::lower(*program, r.diagnostics);
    }
  }
  // The tree is freed before the passes run: the IR they build reuses its
  // memory instead of growing the heap past it (a long program's tree is
  // about as large as its IR).
  if (lowered) r.output = backend::compile(std::move(*lowered), request.level, r.diagnostics, r.log, request.passes);
  if (r.diagnostics.has_errors()) r.output.reset();
  return r;
}

}  // namespace

CompileResult compile_file(const std::string& path, const CompileRequest& request, Diagnostics diags) {
  return compile_parsed(
      [&](SourceManager& sm, Diagnostics& d) { return frontend::parse_program(path, request.frontend, sm, d); },
      request, std::move(diags));
}

CompiledForTest compile_nqc_file(const std::string& path, const CompileRequest& request) {
  CompileResult r = compile_file(path, request);
  CompiledForTest t;
  if (r.output) t.image = std::move(r.output->image);
  for (const auto& raw : r.diagnostics.all()) {
    if (raw.severity == Severity::Note) continue;
    // Placed as printed: a problem inside a standard-library macro at the
    // line that used the macro. Only diagnostics in the test file itself
    // have lines a test can name.
    Diagnostic d = as_reported(raw, r.sources);
    bool in_file = d.span.begin.valid() && r.sources.path(d.span.begin.file) == path;
    t.messages.push_back({d.severity == Severity::Error, in_file ? static_cast<int>(d.span.begin.line) : 0, d.message});
  }
  return t;
}

namespace {

// The first 4 KiB of FILE, or nullopt when it is no regular file one can read.
std::optional<std::string> file_head(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  // A read that failed (EIO: /proc/self/mem, a bad disk) is no file one can
  // read, not an empty one: `compare` took it for source and, when neither
  // compiler could read it, said "nothing to compare" (exit 5).
  if (in.bad()) return std::nullopt;
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

}  // namespace

namespace {

bool has_extension(const std::string& path, std::string_view lower_ext) {
  std::string ext = std::filesystem::path(path).extension().string();
  return std::equal(ext.begin(), ext.end(), lower_ext.begin(), lower_ext.end(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// A folder given as the program: in the words `rcxc compile` uses for a
// folder named like a source, so `download DIR.nqc` and `compile DIR.nqc`
// say the same; the image reader's words for DIR.rcx; both for other names.
std::string folder_as_program(const std::string& path) {
  if (has_extension(path, ".nqc") || has_extension(path, ".nqh"))
    return fmt::format("{}: is a directory, not a source file", path);
  if (named_as_image(path)) return fmt::format("{}: is a directory, not an .rcx image", path);
  return fmt::format("{}: is a directory, not a source file or an .rcx image", path);
}

}  // namespace

bool named_as_image(const std::string& path) { return has_extension(path, ".rcx"); }

std::string non_source_kind(const std::string& path) {
  auto head = file_head(path);
  bool image = named_as_image(path) || (head && rcx::starts_as_image(*head));
  return image ? "an .rcx image" : "binary data";
}

std::optional<bool> is_nqc_source(const std::string& path) {
  auto read = file_head(path);
  if (!read) return std::nullopt;
  const std::string& head = *read;
  if (named_as_image(path)) return false;
  return !rcx::holds_binary_data(head);
}

namespace {

// FILE "-": an image or NQC source on the standard input, told apart as
// files are (the signature "RCXI"), after reading it once.
std::variant<rcx::Image, std::string> load_standard_input(const CompileRequest& request) {
  // Named members, not a structured binding: clang before 16 cannot capture
  // a binding in the lambda below.
  frontend::SourceRead source = frontend::read_source(std::string(frontend::kStandardInput));
  const std::string& name = source.name;
  auto& read = source.bytes;
  if (auto* problem = std::get_if<rcx::FileProblem>(&read))
    return *problem == rcx::FileProblem::TooLarge ? rcx::too_large_message(name, rcx::kSourceFile)
                                                  : "cannot read the standard input";
  std::string& bytes = std::get<std::string>(read);
  if (rcx::starts_as_image(bytes)) {
    auto image = rcx::read_image({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()});
    if (auto* e = std::get_if<rcx::ImageError>(&image)) return name + ": " + e->message;
    return std::get<rcx::Image>(std::move(image));
  }
  // As a file holding them would be: compiled, binary bytes make a screen
  // of "stray character" errors, each quoting its line raw to the terminal.
  if (rcx::holds_binary_data(bytes)) return name + ": binary data, neither NQC source nor an .rcx image";
  CompileResult compiled = compile_parsed(
      [&](SourceManager& sm, Diagnostics& d) {
        return frontend::parse_source(name, std::move(bytes), request.frontend, sm, d);
      },
      request, {});
  std::cerr << render_all(compiled.diagnostics, compiled.sources, {});
  if (!compiled.output) return name + ": the program does not compile";
  return std::move(compiled.output->image);
}

}  // namespace

std::optional<std::string> special_file_problem(const std::string& path, Takes takes, std::string_view reads) {
  if (path == frontend::kStandardInput) return std::nullopt;
  std::error_code ec;
  auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status) || std::filesystem::is_regular_file(status) ||
      std::filesystem::is_directory(status))
    return std::nullopt;
  return fmt::format("{}: not a file{} (a device, a pipe or a socket); {}", path,
                     takes == Takes::FilesAndFolders ? " or a folder" : "", reads);
}

std::optional<std::string> unused_compiler_options(const std::string& path, const CompilerArgs& args) {
  bool given = !args.include_dirs.empty() || !args.defines.empty() || !args.undefines.empty() || args.no_stdlib ||
               args.optimize != CompilerArgs{}.optimize;
  if (!given || path == frontend::kStandardInput || is_nqc_source(path) != false) return std::nullopt;
  return "note: " + path + " is an .rcx image: -I, -D, -U, -n and -O apply to NQC source and were not used";
}

std::variant<rcx::Image, std::string> load_program(const std::string& path, const CompileRequest& request) {
  // A file that cannot be read (missing, unreadable) is the image reader's
  // to explain: it names the file and the reason.
  if (path == frontend::kStandardInput) return load_standard_input(request);
  if (auto problem = special_file_problem(path, Takes::Files, "give an NQC source file or an .rcx image, or '-' for the standard input")) return *problem;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return folder_as_program(path);
  if (is_nqc_source(path).value_or(false)) {
    CompileResult compiled = compile_file(path, request);
    std::cerr << render_all(compiled.diagnostics, compiled.sources, {});
    if (!compiled.output) return fmt::format("{}: the program does not compile", path);
    return std::move(compiled.output->image);
  }
  // Binary bytes that neither are named .rcx nor start as an image: "offset
  // 0: not an RCX image" of a file named prog.nqc read as if it had been
  // taken for an image on purpose. As for the standard input.
  if (auto head = file_head(path); head && !named_as_image(path) && !rcx::starts_as_image(*head))
    return fmt::format("{}: binary data, neither NQC source nor an .rcx image", path);
  auto image = rcx::read_image_file(path);
  if (auto* e = std::get_if<rcx::ImageError>(&image)) return e->message;
  return std::get<rcx::Image>(std::move(image));
}

}  // namespace rcxc::cli
