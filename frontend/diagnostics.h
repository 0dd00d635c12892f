// Source spans and diagnostics: the shared vocabulary for every stage that
// reports a problem in the user's program (lexer to backend).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/warnings.h"

namespace rcxc {

// A position in a source file. Lines and columns count from 1; column counts
// bytes. `file` is an index into SourceManager's file table. `expansion` is 0
// for text read directly from a file; for a token that came out of a macro's
// body it is 1 + the index of that expansion in SourceManager::expansions(),
// and the position is where the token is spelled in the #define.
struct SourceLoc {
  std::uint32_t file = 0;
  std::uint32_t line = 0;
  std::uint32_t column = 0;
  std::uint32_t expansion = 0;
  bool valid() const { return line != 0; }
  bool operator==(const SourceLoc&) const = default;
};

// Whether `a` comes before `b` in the text (both in the same file).
inline bool before(const SourceLoc& a, const SourceLoc& b) {
  return a.line < b.line || (a.line == b.line && a.column < b.column);
}

// A half-open range [begin, end) within one file.
struct SourceSpan {
  SourceLoc begin;
  SourceLoc end;
  bool operator==(const SourceSpan&) const = default;
};

struct Note {
  SourceSpan span;
  std::string message;
};

// One use of a macro: which macro, and where it was used (the use itself may
// lie inside another expansion, making a chain back to the user's text).
struct MacroExpansion {
  std::string macro;
  SourceSpan site;
  // Nothing came out of it: an error covering the site names the macro,
  // since the text there shows tokens the parser never saw.
  bool empty = false;
};

// `text` with each CR that no LF follows turned into LF: a lone CR ends a
// line, as nqc reads classic Mac OS files and as LSP counts lines. In
// place, so every offset stays the text's.
std::string with_lone_crs_as_lf(std::string text);

// Owns the text of every file read during one compilation, so diagnostics can
// quote source lines long after the lexer is done with them. The lexer's
// tokens are views of these texts: a file's text stays where it is for as
// long as the SourceManager lives (moving the SourceManager moves no text).
class SourceManager {
 public:
  std::uint32_t add(std::string path, std::string text);
  const std::string& path(std::uint32_t file) const { return files_.at(file).path; }
  const std::string& text(std::uint32_t file) const { return files_.at(file).text; }
  // Keeps text the preprocessor made (a pasted or stringized token, a -D
  // value) for the tokens that view it; the view stays valid as a file's.
  std::string_view keep(std::string text) { return made_.emplace_back(std::move(text)); }
  std::size_t size() const { return files_.size(); }
  // The text of line `line` of `file`, without its newline ("" if out of range).
  std::string_view line(std::uint32_t file, std::uint32_t line) const;

  // Macro expansions, so diagnostics can say "in expansion of macro X".
  // Returns the value to store in SourceLoc::expansion (1-based).
  std::uint32_t add_expansion(MacroExpansion e);
  const MacroExpansion& expansion(std::uint32_t id) const { return expansions_.at(id - 1); }
  std::size_t expansion_count() const { return expansions_.size(); }
  // The notes "in expansion of macro X" for a location, innermost first.
  std::vector<Note> expansion_notes(const SourceLoc& loc) const;
  void mark_expansion_empty(std::uint32_t id) { expansions_.at(id - 1).empty = true; }
  // The notes "macro X expands to nothing" for each such use written in
  // the text `span` covers, when it covers part of one line (not inside
  // another macro's expansion).
  std::vector<Note> empty_expansion_notes(const SourceSpan& span) const;

  // The standard library (rcx.nqh): a problem its text shows is the user's
  // use of it, so diagnostics move to the user's line (as_reported).
  void mark_library(std::uint32_t file);
  bool is_library(std::uint32_t file) const { return file < files_.size() && files_[file].library; }

  // Where `file` was #included (so diagnostics in it can say so).
  void set_include_site(std::uint32_t file, SourceSpan site);
  // The #include directive that read `file` (from its '#' to its end), or
  // an invalid span for a file no directive read.
  SourceSpan include_site(std::uint32_t file) const { return files_.at(file).included_from; }
  // The notes "FILE was included from here" for a location, innermost first.
  std::vector<Note> include_notes(const SourceLoc& loc) const;

 private:
  struct File {
    std::string path;
    std::string text;
    std::vector<std::size_t> line_starts;
    SourceSpan included_from;  // invalid when not #included
    bool library = false;
  };
  // Deques: adding a file or a made text moves none already there, so the
  // views tokens hold of them stay valid (a vector would move short,
  // in-place strings when it grows).
  std::deque<File> files_;
  std::deque<std::string> made_;
  std::vector<MacroExpansion> expansions_;
};

enum class Severity : std::uint8_t { Note, Warning, Error };
std::string_view severity_name(Severity s);

struct Diagnostic {
  Severity severity = Severity::Error;
  SourceSpan span;
  std::string message;
  std::vector<Note> notes;
  // An error the parser read past as if the text were right (an RCX 2
  // statement, a malformed number, a pointer): the code around it is whole
  // and can still be checked.
  bool parsed_past = false;
  // The file a diagnostic without a position is about, when it is not the
  // program being compiled (which is the default: SourceManager's file 0).
  std::string file;
  // Which warning this is (kept when -Werror makes it an error), so users
  // can turn it off by name and editors can tell kinds apart.
  std::optional<WarningKind> warning;
};

// Collects diagnostics of one compilation. Warnings are silenced (-w,
// -Wno-NAME) or promoted to errors (-Werror) here, once, for every stage.
class Diagnostics {
 public:
  WarningPolicy policy;

  Diagnostic& error(SourceSpan span, std::string message);
  Diagnostic& warning(SourceSpan span, WarningKind kind, std::string message);
  void add(Diagnostic d);

  const std::vector<Diagnostic>& all() const { return list_; }
  // The `index`th diagnostic, to add a note found later (index < all().size()).
  Diagnostic& at(std::size_t index) { return list_.at(index); }
  std::size_t error_count() const;
  bool has_errors() const { return error_count() != 0; }

 private:
  std::vector<Diagnostic> list_;
  Diagnostic discarded_;
};

// `d` as the user should see it: an error inside a standard-library macro
// (Random() without its argument) is placed where the user's text used the
// macro, with the library line as a note, and a span that runs from a
// macro's text into the user's (an argument `BASE + site`) is the text as
// written in the call. Rendering applies it.
Diagnostic as_reported(const Diagnostic& d, const SourceManager& sm);

// gcc-style text: "file:line:col: error: message", the source line, a caret
// under the span, then each note the same way.
// With `color`, ANSI colours as gcc prints them on a terminal.
std::string render_text(const Diagnostic& d, const SourceManager& sm, bool color = false);
// " [-Wunused-variable]" for a warning ("[-Werror=...]" once promoted), as
// gcc and clang name the option that turns it off; "" for other messages.
std::string warning_option_tag(const Diagnostic& d);
// One JSON object (a single line) with file, line, column, end, severity,
// message, code (a warning's name) and notes, for IDEs.
std::string render_json(const Diagnostic& d, const SourceManager& sm);

// The diagnostics in the order of the text they are about, as a reader meets
// it: a message in a macro's body counts where the macro is used, one in an
// #included file where the #include is. Stages report in their own order
// (preprocessor, parser, checks, code generation); readers want line order.
// Those without a position come last, in the order they were reported.
std::vector<const Diagnostic*> in_source_order(const Diagnostics& diags, const SourceManager& sm);

inline constexpr std::size_t kDefaultMaxErrors = 20;

// The character a well-formed UTF-8 sequence at the start of `text` spells,
// and its length in bytes; length 0 when the bytes are none (a lone
// continuation byte, a sequence cut short or overlong, a surrogate), and 1
// for ASCII. Columns count bytes; the lexer and the caret line need to know
// where a character ends.
struct Utf8Char {
  char32_t code = 0;
  std::size_t length = 0;
};
Utf8Char decode_utf8(std::string_view text);

// A source line as printed under a message, and the caret line's lead-in
// (the line's tabs kept, so the caret lines up under the text). A line of a
// generated or minified program can be hundreds of kilobytes, and printing
// it whole under each of thousands of messages wrote gigabytes: a line over
// 160 bytes shows a window around `column0` (0-based bytes), cut at
// character boundaries and marked "...". `width` is the span's, clamped to
// what is shown.
struct QuotedLine {
  std::string text;
  std::string lead_in;
  std::size_t width = 1;
};
QuotedLine quote_line(std::string_view line, std::size_t column0, std::size_t width);

// How a whole compilation's diagnostics are printed.
struct RenderOptions {
  bool json = false;  // one JSON object per line instead of text
  // Once this many errors are printed, the next error is replaced by a note
  // saying how many are left out, and printing stops: a file that is not NQC
  // at all would otherwise bury the first, useful error. 0 prints all.
  std::size_t max_errors = kDefaultMaxErrors;
  bool color = false;  // ANSI colours (--color; on a terminal by default)
};
std::string render_all(const Diagnostics& diags, const SourceManager& sm, const RenderOptions& options);

}  // namespace rcxc
