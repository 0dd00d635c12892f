// What the language server knows about one open document: the compiler's
// diagnostics for it and every name in it and in the files it reads (the
// standard library, #includes), with where each is defined and used.
//
// The diagnostics come from the compiler exactly as `rcxc compile` reports
// them. The names come from a second, lenient pass (preprocess and parse,
// no checks), so a program with errors in it still has its tasks, functions
// and variables to hover, complete and jump to.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "frontend/diagnostics.h"
#include "frontend/frontend.h"

namespace rcxc::lsp {

enum class DefKind : std::uint8_t { Task, Sub, Function, Global, Local, Param, Label, Macro };
std::string_view def_kind_name(DefKind k);

// A place in one of the index's files; lines and columns count from 1, the
// column in bytes (the compiler's convention).
struct Place {
  std::uint32_t file = 0;
  std::uint32_t line = 0;
  std::uint32_t column = 0;
  bool operator==(const Place&) const = default;
};

struct Range {
  Place begin;
  Place end;  // same file, exclusive
};

struct Definition {
  std::string name;
  DefKind kind = DefKind::Global;
  Range at;                     // the declaring name
  Range extent;                 // the whole declaration as far as known (tasks, subs, functions: to the body's end)
  std::string signature;        // e.g. "void OnFwd(const int outputs)", "#define OUT_A 1"
  std::string doc;              // the comment above the definition, without `//`
  std::optional<Range> scope;   // Local, Param, Label: the body they belong to
  std::string owner;            // Local, Param, Label: the task, sub or function
};

// One identifier as spelled in a file (comments and strings excluded).
struct Occurrence {
  std::string name;
  Range at;
};

// A compiler diagnostic placed in the document itself: problems inside an
// included file or a macro are shown where the document includes or uses it.
struct DocDiagnostic {
  Severity severity = Severity::Error;
  std::uint32_t line = 0;  // 1-based; 0 when the problem has no position
  std::uint32_t column = 0;
  std::uint32_t end_line = 0;
  std::uint32_t end_column = 0;
  std::string message;
  std::optional<WarningKind> warning;  // which warning, for the code editors show and filter by
  struct Related {
    std::string path;  // "" when the note has no position
    std::uint32_t line = 0, column = 0, end_line = 0, end_column = 0;
    std::string message;
  };
  std::vector<Related> related;
};

// How the program uses a variable at one place, as the syntax tree says:
// assigned (`=`, `+=` and the other assignment operators, `++`, `--`),
// passed whole to a call (the callee may take it by reference), or read.
enum class Access : std::uint8_t { Read, Argument, Write };

// A character of more than one byte, on one line of a file: its bytes
// [start, end) from the line's start (0-based; `end` may pass the line's end
// when the text is cut short) and the UTF-16 units from the line's start
// through it.
struct WideChar {
  std::uint32_t line = 0;
  std::uint32_t start = 0, end = 0;
  std::uint32_t units = 0;
};

struct Index {
  SourceManager sm;                 // every file read, the document is file `main_file`
  std::uint32_t main_file = 0;
  std::vector<bool> is_stdlib;      // by file: the embedded standard library
  // The `-D` options, one `-D NAME=VALUE` a line, as a file of their own:
  // the macros they define are placed there (nothing an editor can open).
  std::optional<std::uint32_t> command_line;
  std::vector<Definition> defs;
  std::vector<Occurrence> occurrences;
  std::vector<DocDiagnostic> diagnostics;
  // Where a name is assigned or passed to a call: from the place (file,
  // line, column) its expression begins, to the line and column it ends
  // (a name in parentheses begins at the '('); a name in a macro's body
  // counts where the body spells it.
  struct Accessed {
    std::uint32_t end_line = 0, end_column = 0;
    Access access = Access::Read;
  };
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, Accessed> accesses;
  // By file, in order: its characters of more than one byte, so that a
  // column converts to UTF-16 without reading the line up to it (a line of
  // 60,000 declarations made a symbol list take minutes). Empty for a
  // document past kMaxDocument, which has no names to place.
  std::vector<std::vector<WideChar>> wide_chars;
};

// The largest document compiled, as rcxc compile caps a source file
// (rcx::kSourceFile); a larger one gets one diagnostic and no names.
inline constexpr std::size_t kMaxDocument = std::size_t{1} << 20;

// Compiles `text` as the file at `path` (includes are searched next to it
// and in options.include_dirs) and indexes what it defines and uses.
// `warnings`: which warnings the document's diagnostics give (the client's
// initializationOptions.warnings, as -W options).
Index build_index(const std::string& path, const std::string& text, const frontend::Options& options,
                  const WarningPolicy& warnings = {});

// The identifier at (line, column) of `file`, if the position is on one.
const Occurrence* occurrence_at(const Index& index, std::uint32_t file, std::uint32_t line, std::uint32_t column);

// Whether `a` comes before `b` in their file (the file is not compared).
bool before(const Place& a, const Place& b);

// Whether `p` lies in `r` (its end excluded).
bool contains(const Range& r, const Place& p);

// What the identifier `name` at `where` refers to: a macro, else the
// innermost local, parameter or label in scope, else a top-level name.
const Definition* resolve(const Index& index, const std::string& name, const Place& where);

// The bytes of the UTF-8 character that `lead` starts (1 for a byte that
// starts none, such as a stray continuation byte).
std::size_t utf8_length(unsigned char lead);

// The UTF-16 column (from 0) of the byte column `at.column` (from 1) of
// its line, as LSP counts: a character begun before the column counts
// whole, a 4-byte one as two units, and columns past the line's end one
// unit each.
std::uint32_t utf16_column(const Index& index, const Place& at);

// What the identifier at `at` does with its variable (Read when the tree
// has nothing there, e.g. in a line the parser could not read).
Access access_at(const Index& index, const Place& at);

// Each identifier of `file` with what it refers to (nullptr: nothing
// known), in source order; the names are looked up in one table, so a
// whole document costs about as much as its identifiers.
std::vector<std::pair<const Occurrence*, const Definition*>> resolve_file(const Index& index, std::uint32_t file);

// Whether `file` is the standard library, or the `-D` options.
bool in_stdlib(const Index& index, std::uint32_t file);
bool on_command_line(const Index& index, std::uint32_t file);

// Every occurrence that refers to `def` (its own declaration included when
// `with_declaration`), in file then source order.
std::vector<Range> references(const Index& index, const Definition& def, bool with_declaration);

// The definitions visible at `where` (in scope locals and parameters, then
// every macro and top-level name), one per name, for completion.
std::vector<const Definition*> visible_at(const Index& index, const Place& where);

// The call whose argument list holds `where` in the document: the innermost
// '(' still open there that follows a name (a '(' after a keyword or an
// operator only groups), and how many of its commas come before `where`.
struct CallSite {
  std::string callee;
  Place callee_at;
  std::size_t argument = 0;  // from 0
};
std::optional<CallSite> call_at(const Index& index, const Place& where);

// Every call in `file` (a name followed by '(' as call_at reads one, the
// declaring name of a function or macro included), with where each
// argument begins; an empty argument (`f(, x)`) is left out.
struct CallArgument {
  std::size_t position = 0;  // from 0
  Place at;                  // its first token
  std::string only_name;     // the argument when it is one name, else empty
};
struct CallArguments {
  std::string callee;
  Place callee_at;
  std::vector<CallArgument> arguments;
};
std::vector<CallArguments> calls_in(const Index& index, std::uint32_t file);

// Where the body of `def` (a task, sub or function of `file`) opens: the
// first '{' after its name; none when the text has no such brace.
std::optional<Place> body_opening(const Index& index, const Definition& def);

// The parameter list of a function's, sub's or function-like macro's
// signature: each parameter as a byte range [begin, end) of `signature`,
// and the offset of the ')' that closes the list. None for other names.
struct ParameterList {
  std::vector<std::pair<std::size_t, std::size_t>> params;
  std::size_t close = 0;
};
std::optional<ParameterList> parameter_list(const Definition& def);

// Whether `s` is spelled as an identifier (letters, digits and _, not
// starting with a digit), and whether the parser reads `name` as a name (an
// identifier and no keyword).
bool is_identifier(std::string_view s);
bool is_plain_name(std::string_view name);

// A definition that renaming the name at `uses` (a definition's references,
// its declaration included) to `new_name` would collide with: one that
// `new_name` already means at one of them (the renamed uses would mean it).
const Definition* rename_clash(const Index& index, const std::vector<Range>& uses, const std::string& new_name);

// Names close to `name` (edit distance, case differences counting less), best
// first, at most `limit`: the "did you mean" candidates for an unknown name.
std::vector<std::string> similar_names(const Index& index, const std::string& name, const Place& where,
                                       std::size_t limit = 3);

// Edit distance (insertions, deletions, substitutions, transpositions).
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace rcxc::lsp
