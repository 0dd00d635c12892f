// The one way the CLI turns an NQC source file into a program image in
// memory: `rcxc test`, `run`, `compare`, `download` and `disasm` all compile
// through here, with the options `rcxc compile` takes, so they behave
// exactly like `rcxc compile`.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "backend/codegen.h"
#include "frontend/diagnostics.h"
#include "frontend/frontend.h"
#include "ir/passes.h"
#include "rcx/image.h"
#include "verify/testspec.h"

namespace rcxc::cli {

// The compiler's options as the command line gives them (-I, -D, -U, -n,
// -O), shared by every command that compiles.
struct CompilerArgs {
  std::vector<std::string> include_dirs;
  std::vector<std::string> defines;
  std::vector<std::string> undefines;
  bool no_stdlib = false;
  std::string optimize = "2";
};

// Registers -I, -D, -U, -n and -O0/-O1/-O2/-Os on `cmd`, storing into `args`.
void add_compiler_options(CLI::App* cmd, CompilerArgs& args);
// What the option parser cannot judge (macro names must be identifiers), or
// nullopt when the options are good.
std::optional<std::string> bad_compiler_arguments(const CompilerArgs& args);
// Parses compiler options given as words (a test's `@options` line) with
// the same rules; relative -I folders are taken from `base_dir`. The error
// says which word is wrong.
std::variant<CompilerArgs, std::string> parse_compiler_options(const std::vector<std::string>& words,
                                                               const std::string& base_dir);
// The command line's options, then a program's own `@options` words (read
// from `file`): their -I, -D and -U come after the command line's, their -n
// and -O win. Used by `rcxc test` and `rcxc run`, so both compile alike.
std::variant<CompilerArgs, std::string> with_file_options(const CompilerArgs& command_line,
                                                          const std::vector<std::string>& words,
                                                          const std::string& file);
// The words that give nqc the same -I, -D, -U and -n (nqc has no levels).
std::vector<std::string> nqc_arguments(const CompilerArgs& args);

struct CompileRequest {
  frontend::Options frontend;
  ir::OptLevel level = ir::OptLevel::O2;
  ir::PassOptions passes;
};
CompileRequest compile_request(const CompilerArgs& args);

struct CompileResult {
  SourceManager sources;
  Diagnostics diagnostics;
  std::optional<backend::Output> output;  // nullopt when there were errors
  ir::Log log;                            // what the passes decided (-v)
  std::vector<std::string> globals;       // the file-scope variables, stdlib's included
};

// Frontend, lowering, passes and code generation for the file at `path`.
// `diags` may come preconfigured (-Werror, -w).
CompileResult compile_file(const std::string& path, const CompileRequest& request, Diagnostics diags = {});

// The same, reduced to what `rcxc test` needs: the image and the messages.
struct CompiledForTest {
  std::optional<rcx::Image> image;
  std::vector<rcx::semtest::CompilerMessage> messages;
};
CompiledForTest compile_nqc_file(const std::string& path, const CompileRequest& request);

// Whether FILE holds NQC source rather than an .rcx image. Content first: a
// file that starts with the image signature "RCXI" is an image whatever its
// name; otherwise a name ending in .rcx (any case) or bytes no text has (a
// NUL) make it an image, which the image reader then refuses with a reason;
// anything else is source. nullopt when the file cannot be read.
std::optional<bool> is_nqc_source(const std::string& path);
// Whether FILE's name ends in .rcx, in any case (nqc's own test for an image).
bool named_as_image(const std::string& path);
// What a FILE that is_nqc_source calls no source holds: "an .rcx image"
// (its signature or its name says so) or "binary data".
std::string non_source_kind(const std::string& path);

// What a command reads, for the message of special_file_problem().
enum class Takes : std::uint8_t { Files, FilesAndFolders };
// PATH names something that exists but is neither a regular file nor a
// folder: a device, a pipe or a socket, which no command reads as a program
// or firmware (/dev/null would be an empty program, an image "too short" or
// firmware with "no data records", a pipe is
// read once where a command may look at a file twice). The message, as
// "P: not a file (a device, a pipe or a socket); `reads`"; nullopt for
// anything else ("-", a missing file or a folder, which the readers explain).
std::optional<std::string> special_file_problem(const std::string& path, Takes takes, std::string_view reads);

// For `run`, `disasm` and `download` given an image with -I, -D, -U, -n or
// -O: a note that they were not used (there is nothing to compile), or
// nullopt. Without it they would be taken and ignored without a word.
std::optional<std::string> unused_compiler_options(const std::string& path, const CompilerArgs& args);

// FILE as a program image: source is compiled in memory (diagnostics go to
// stderr), an image is read. The error names the file.
std::variant<rcx::Image, std::string> load_program(const std::string& path, const CompileRequest& request);

}  // namespace rcxc::cli
