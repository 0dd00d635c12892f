// The frontend's entry points: source file in, checked AST (or diagnostics)
// out. Everything is reentrant: all state lives in the arguments.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"
#include "rcx/file_read.h"

namespace rcxc::frontend {

struct Options {
  std::vector<std::string> include_dirs;                    // -I, searched in order
  std::vector<std::pair<std::string, std::string>> defines;  // -D NAME[=VALUE] ("1" if no value)
  std::vector<std::string> undefines;                       // -U NAME
  bool no_stdlib = false;                                   // -n: do not include rcx.nqh
  // Parse and check every standard-library function, not only those the
  // program reaches. The result is the same (tests compare the two); the
  // default skips the library's unused functions for speed.
  bool whole_library = false;
  // The text an editor holds for an included file, by its absolute path
  // (lexically normal), read instead of the disk (rcxc lsp's unsaved buffers).
  const std::map<std::string, std::string>* unsaved = nullptr;

  // Adds `-D`'s argument: NAME or NAME=VALUE.
  void define(const std::string& option);
};

// A `path` of "-" is the standard input, as on nqc's command line: it is
// named <stdin> in messages, and its relative #includes are searched from
// the current folder.
inline constexpr std::string_view kStandardInput = "-";
inline constexpr std::string_view kStandardInputName = "<stdin>";

// The bytes of source `path` (the standard input for "-"), read up to the
// cap every source file has, and the name it goes by in messages.
struct SourceRead {
  std::string name;
  std::variant<std::string, rcx::FileProblem> bytes;
};
SourceRead read_source(const std::string& path);

// Preprocesses, parses and checks the file at `path`. Returns the annotated
// program when no error was reported (warnings are allowed), else nullopt;
// either way every problem is in `diags`, located through `sm`.
std::optional<ast::Program> parse_program(const std::string& path, const Options& options, SourceManager& sm,
                                          Diagnostics& diags);

// The same for source text held in memory (`name` is used in diagnostics and
// as the folder for relative includes).
std::optional<ast::Program> parse_source(const std::string& name, std::string text, const Options& options,
                                         SourceManager& sm, Diagnostics& diags);

// `rcxc compile -E`: the preprocessed text of `path` and of everything it
// includes (the stdlib too unless -n), with `# LINE "FILE"` markers where the
// source file changes; nullopt after errors.
std::optional<std::string> preprocess_file(const std::string& path, const Options& options, SourceManager& sm,
                                           Diagnostics& diags);

// Folds a constant expression with 16-bit wrap-around (nullopt if it is not
// constant). Lowering can use it after substituting inline-function
// parameters, e.g. to fold `__source_arg(SENSOR_1)`. Division by zero and
// other errors are reported to `diags` when it is non-null.
std::optional<std::int16_t> fold_constant(const ast::Expr& e, Diagnostics* diags = nullptr);

}  // namespace rcxc::frontend
