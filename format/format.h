// The NQC source formatter (`rcxc format`, the language server's
// "Format Document"): lays a program out again in one style (docs/format.md)
// without changing what it means. It works on the lexer's tokens and
// comments, before preprocessing, so it formats any text that lexes, even
// one with syntax errors, and keeps every directive as written (and every
// #if branch left out whatever the macros, #if 0, or holding text that is
// no token, as the compiler allows there).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>

#include "rcx/file_read.h"

namespace rcxc::format {

struct Style {
  int indent = 2;  // spaces per level of nesting (docs/format.md says why 2)
};
inline constexpr int kMinIndent = 1;
inline constexpr int kMaxIndent = 8;

// The largest text formatted: the compiler's own cap on a source file.
inline constexpr std::size_t kMaxSource = rcx::kSourceFile.max_bytes;

// Why a text was not formatted: the whole message, ready to show.
struct Refusal {
  std::string message;
};

// The formatted text, or why there is none. The result lexes to the same
// tokens and comments as `text`, with every directive on lines of its own as
// before (checked on every call: a layout that would break this is refused,
// not returned), and formatting it again gives it back unchanged. A UTF-8
// byte-order mark at the start is kept, and the text after it laid out.
std::variant<std::string, Refusal> format_source(std::string_view text, const Style& style = {});

}  // namespace rcxc::format
