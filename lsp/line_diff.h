// The lines two texts differ in, for answering "format selection" with
// edits of the selected lines only (the formatter lays out whole files).
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

namespace rcxc::lsp {

// A text's lines as LSP counts them, each with its end (LF, CR LF or a lone
// CR); a last line without one is a line too, and "" has none.
std::vector<std::string_view> split_lines(std::string_view text);

// Old lines [old_begin, old_end) become new lines [new_begin, new_end); an
// empty old range is an insertion before old line old_begin.
struct Hunk {
  std::size_t old_begin = 0, old_end = 0;
  std::size_t new_begin = 0, new_end = 0;
};

// The hunks of a shortest edit from `a` to `b` (Myers' algorithm), in
// order, none touching another. Past kMaxEdits lines inserted and deleted,
// what lies between the common first and last lines is one hunk: the
// search's memory grows with the square of the edits.
inline constexpr std::size_t kMaxEdits = 2000;
std::vector<Hunk> line_hunks(const std::vector<std::string_view>& a, const std::vector<std::string_view>& b);

}  // namespace rcxc::lsp
