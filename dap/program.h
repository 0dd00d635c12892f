// A program compiled for debugging: the image the emulator runs, and what a
// debugger needs to speak of it in the user's terms. Which source line each
// instruction is (from the compiler's own Emitted::span, as listings use it),
// where statements start, and which variable lives in which slot (from the
// compiler's slot allocation).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "frontend/frontend.h"
#include "ir/passes.h"
#include "rcx/image.h"

namespace rcxc::dap {

// A line of the user's text: files[file] at `line` (1-based); file < 0 when
// an instruction has none (a temporary the compiler made at no line).
struct Place {
  int file = -1;
  int line = 0;
  bool valid() const { return file >= 0; }
  bool operator==(const Place&) const = default;
};

// One task or subroutine as the compiler emitted it.
struct FragmentLines {
  rcx::FragmentType type = rcx::FragmentType::Task;
  int index = 0;
  std::string name;
  int code_size = 0;
  int function = -1;              // index into DebugProgram::functions, -1 for a sub the compiler made (-Os)
  std::vector<int> addresses;     // of each instruction, ascending
  // The user's line of each instruction (an inline function's code is at
  // its call, as the compiler places it). One whose span is in the
  // standard library's text, or at no line, counts as the line before it.
  std::vector<Place> places;
  // Whether an instruction begins a statement (its line differs from the
  // instruction before it): breakpoints and steps stop there.
  std::vector<bool> starts;
  Place end;                      // the closing brace: a sub's appended return, a task's end
};

struct Variable {
  std::string name;
  int slot = 0;
};

struct Function {
  std::string name;
  Place begin, end;               // the lines it spans in its file
  std::vector<Variable> locals;   // the locals declared in it that have slots
};

struct DebugProgram {
  rcx::Image image;
  std::vector<std::string> files;  // absolute, lexically normal paths by SourceManager index
  std::vector<FragmentLines> fragments;
  std::vector<Function> functions;
  std::vector<Variable> globals;
  // Variables with slots the debugger could not tie to a declaration
  // (shown with the globals, by the names the image gives them).
  bool slots_exact = true;

  // The fragment a task runs: `sub` >= 0 for a subroutine, else task `task`.
  const FragmentLines* fragment(int task, int sub) const;
  // The place of the instruction at `pc` (the end for pc past the code).
  Place place_at(const FragmentLines& f, int pc) const;
  // Whether `pc` begins a statement (the end counts as one).
  bool starts_statement(const FragmentLines& f, int pc) const;
  // The file index of `path` (compared as absolute, normal paths), or -1.
  int file_index(const std::string& path) const;
};

struct CompileOutcome {
  std::optional<DebugProgram> program;  // nullopt when it did not compile
  std::string messages;                 // the compiler's diagnostics, file:line:col as rcxc compile prints them
};

CompileOutcome compile_for_debug(const std::string& path, const frontend::Options& options, ir::OptLevel level);

}  // namespace rcxc::dap
