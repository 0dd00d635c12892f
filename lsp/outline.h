// The shape of a document as an editor shows it: the regions it can fold,
// read from the text alone (so a program with errors folds as well), and
// how well a name matches what was typed in a workspace symbol search.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace rcxc::lsp {

enum class FoldKind : std::uint8_t {
  Block,        // { ... }: a task's, sub's or function's body, a loop's, ...
  Comment,      // a /* */ comment, or a run of lines holding only // comments
  Imports,      // a run of #include lines
  Conditional,  // #if/#ifdef/#ifndef to #elif/#else/#endif, and each part after
};

// Lines count from 1; folding hides the lines after `first` up to `last`.
// A closing '}' or '#endif' that starts its line stays visible: the fold
// ends on the line before it.
struct Fold {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  FoldKind kind = FoldKind::Block;
};

// The folds of `text` by first line (the larger first), each region once.
// A block starts on the line of its header (`task main()`, `while (x)`,
// `else`, `do`, `asm`) when the '{' is on a later line. Regions of one line are left out.
std::vector<Fold> folds(std::string_view text);

// How `name` matches a workspace symbol query, ignoring case: 0 when it
// starts with the query, 1 when it contains it, 2 when the query's letters
// appear in it in order (`bkof` in `back_off`), none otherwise. An empty
// query matches every name (0).
std::optional<int> symbol_match(std::string_view name, std::string_view query);

}  // namespace rcxc::lsp
