#include "frontend/spelling.h"

#include <algorithm>
#include <cctype>

namespace rcxc::frontend {

std::size_t spelling_distance(std::string_view a, std::string_view b) {
  auto same = [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  };
  // Optimal string alignment distance over three rows.
  std::vector<std::size_t> before(b.size() + 1), previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t cost = same(a[i - 1], b[j - 1]) ? 0 : 1;
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost});
      if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1]))
        current[j] = std::min(current[j], before[j - 2] + 1);
    }
    before.swap(previous);
    previous.swap(current);
  }
  return previous[b.size()];
}

std::optional<std::string> closest_name(std::string_view misspelt, const std::vector<std::string>& candidates) {
  // A third of the name: 'Wiat' is Wait, but 'y' is not 'x'.
  const std::size_t limit = misspelt.size() / 3;
  // The distance costs the product of the lengths: a 20,000-letter name
  // against a global as long took 17 s of CPU. Nobody misspells a name that
  // long, so it gets no suggestion.
  if (misspelt.size() > kMaxSpelledName) return std::nullopt;
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  bool tied = false;
  for (const std::string& c : candidates) {
    if (c == misspelt || c.rfind("__", 0) == 0) continue;
    // At least one edit per letter of difference in length.
    if ((c.size() > misspelt.size() ? c.size() - misspelt.size() : misspelt.size() - c.size()) > limit) continue;
    std::size_t d = spelling_distance(misspelt, c);
    if (d < best_distance) {
      best = c;
      best_distance = d;
      tied = false;
    } else if (d == best_distance && best && *best != c) {
      tied = true;
    }
  }
  if (!best || tied) return std::nullopt;
  return best;
}

std::optional<std::string> name_with_prefix(std::string_view bare, const std::vector<std::string>& candidates) {
  if (bare.size() < 3) return std::nullopt;
  std::optional<std::string> best;
  bool tied = false;
  for (const std::string& c : candidates) {
    if (c.size() <= bare.size() + 1 || !c.ends_with(bare) || c[c.size() - bare.size() - 1] != '_' ||
        c.rfind("__", 0) == 0)
      continue;
    if (!best || c.size() < best->size()) {
      best = c;
      tied = false;
    } else if (c.size() == best->size() && c != *best) {
      tied = true;
    }
  }
  if (!best || tied) return std::nullopt;
  return best;
}

}  // namespace rcxc::frontend
