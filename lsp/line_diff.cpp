#include "lsp/line_diff.h"

#include <cstdint>
#include <optional>

namespace rcxc::lsp {

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\n' && text[i] != '\r') continue;
    if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    lines.push_back(text.substr(start, i + 1 - start));
    start = i + 1;
  }
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

namespace {

using Lines = std::vector<std::string_view>;

// The furthest old line reached on each diagonal k = x - y after d edits,
// kept for every d (diagonals -d-1 .. d+1) to walk the path back.
struct Frontier {
  std::ptrdiff_t d = 0;
  std::vector<std::ptrdiff_t> x;
  std::ptrdiff_t at(std::ptrdiff_t k) const { return x[static_cast<std::size_t>(k + d + 1)]; }
};

// For each old line, whether it is kept, and for each new line, whether it
// was there before; empty when the edit is longer than kMaxEdits.
struct Kept {
  std::vector<bool> old_kept, new_kept;
};

std::optional<Kept> shortest_edit(const Lines& a, const Lines& b, std::size_t a0, std::size_t a1, std::size_t b0,
                                  std::size_t b1) {
  const auto n = static_cast<std::ptrdiff_t>(a1 - a0), m = static_cast<std::ptrdiff_t>(b1 - b0);
  auto same = [&](std::ptrdiff_t x, std::ptrdiff_t y) {
    return a[a0 + static_cast<std::size_t>(x)] == b[b0 + static_cast<std::size_t>(y)];
  };
  std::vector<Frontier> trace;
  Frontier v{0, {0, 0, 0}};
  std::ptrdiff_t edits = -1;
  for (std::ptrdiff_t d = 0; d <= n + m && d <= static_cast<std::ptrdiff_t>(kMaxEdits); ++d) {
    trace.push_back(v);
    Frontier next{d + 1, std::vector<std::ptrdiff_t>(static_cast<std::size_t>(2 * d + 5), 0)};
    bool reached = false;
    for (std::ptrdiff_t k = -d; k <= d; k += 2) {
      std::ptrdiff_t x = (k == -d || (k != d && v.at(k - 1) < v.at(k + 1))) ? v.at(k + 1) : v.at(k - 1) + 1;
      std::ptrdiff_t y = x - k;
      while (x < n && y < m && same(x, y)) ++x, ++y;
      next.x[static_cast<std::size_t>(k + d + 2)] = x;
      if (x >= n && y >= m) reached = true;
    }
    if (reached) {
      edits = d;
      trace.push_back(next);
      break;
    }
    v = std::move(next);
  }
  if (edits < 0) return std::nullopt;
  Kept kept{std::vector<bool>(static_cast<std::size_t>(n), false), std::vector<bool>(static_cast<std::size_t>(m), false)};
  std::ptrdiff_t x = n, y = m;
  for (std::ptrdiff_t d = edits; d >= 0; --d) {
    const Frontier& before = trace[static_cast<std::size_t>(d)];
    std::ptrdiff_t k = x - y;
    std::ptrdiff_t prev_k = (k == -d || (k != d && before.at(k - 1) < before.at(k + 1))) ? k + 1 : k - 1;
    std::ptrdiff_t prev_x = d == 0 ? 0 : before.at(prev_k);
    std::ptrdiff_t prev_y = d == 0 ? 0 : prev_x - prev_k;
    while (x > prev_x && y > prev_y) {
      --x, --y;
      kept.old_kept[static_cast<std::size_t>(x)] = kept.new_kept[static_cast<std::size_t>(y)] = true;
    }
    x = prev_x, y = prev_y;
  }
  return kept;
}

}  // namespace

std::vector<Hunk> line_hunks(const Lines& a, const Lines& b) {
  std::size_t a0 = 0, b0 = 0, a1 = a.size(), b1 = b.size();
  while (a0 < a1 && b0 < b1 && a[a0] == b[b0]) ++a0, ++b0;
  while (a1 > a0 && b1 > b0 && a[a1 - 1] == b[b1 - 1]) --a1, --b1;
  if (a0 == a1 && b0 == b1) return {};
  auto kept = shortest_edit(a, b, a0, a1, b0, b1);
  if (!kept) return {Hunk{a0, a1, b0, b1}};
  std::vector<Hunk> hunks;
  std::size_t i = 0, j = 0;
  const std::size_t n = a1 - a0, m = b1 - b0;
  while (i < n || j < m) {
    if (i < n && j < m && kept->old_kept[i] && kept->new_kept[j]) {
      ++i, ++j;
      continue;
    }
    Hunk h{a0 + i, a0 + i, b0 + j, b0 + j};
    while (i < n && !kept->old_kept[i]) ++i;
    while (j < m && !kept->new_kept[j]) ++j;
    h.old_end = a0 + i;
    h.new_end = b0 + j;
    hunks.push_back(h);
  }
  return hunks;
}

}  // namespace rcxc::lsp
