// The line diff behind "format selection": hunks that turn the old lines
// into the new, as few lines changed as any edit can (checked against a
// plain longest-common-subsequence count on random texts).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "lsp/line_diff.h"

namespace rcxc::lsp {
namespace {

using Lines = std::vector<std::string_view>;

TEST(SplitLines, EachLineKeepsItsEndAsLspCountsThem) {
  EXPECT_EQ(split_lines(""), Lines{});
  EXPECT_EQ(split_lines("a"), (Lines{"a"}));
  EXPECT_EQ(split_lines("a\nb\r\nc\rd"), (Lines{"a\n", "b\r\n", "c\r", "d"}));
  EXPECT_EQ(split_lines("\n\n"), (Lines{"\n", "\n"}));
}

TEST(LineHunks, SameTextsHaveNoneAndOneChangedLineIsOneHunk) {
  Lines a{"x\n", "y\n", "z\n"};
  EXPECT_TRUE(line_hunks(a, a).empty());
  auto h = line_hunks(a, Lines{"x\n", "Y\n", "z\n"});
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h[0].old_begin, 1u);
  EXPECT_EQ(h[0].old_end, 2u);
  EXPECT_EQ(h[0].new_begin, 1u);
  EXPECT_EQ(h[0].new_end, 2u);
  // A line put in after the second: an empty old range before line 2.
  h = line_hunks(a, Lines{"x\n", "y\n", "new\n", "z\n"});
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h[0].old_begin, 2u);
  EXPECT_EQ(h[0].old_end, 2u);
  EXPECT_EQ(h[0].new_begin, 2u);
  EXPECT_EQ(h[0].new_end, 3u);
}

// Lines kept by a longest common subsequence (dynamic programming).
std::size_t common_lines(const Lines& a, const Lines& b) {
  std::vector<std::vector<std::size_t>> l(a.size() + 1, std::vector<std::size_t>(b.size() + 1, 0));
  for (std::size_t i = a.size(); i-- > 0;)
    for (std::size_t j = b.size(); j-- > 0;)
      l[i][j] = a[i] == b[j] ? l[i + 1][j + 1] + 1 : std::max(l[i + 1][j], l[i][j + 1]);
  return l[0][0];
}

TEST(LineHunks, ApplyingThemGivesTheNewTextWithTheFewestLinesChanged) {
  std::mt19937 rng(11);
  const std::vector<std::string> words = {"a\n", "b\n", "c\n", "d\n", "e"};
  for (int round = 0; round < 2000; ++round) {
    Lines a, b;
    for (std::size_t n = rng() % 12; n-- > 0;) a.push_back(words[rng() % words.size()]);
    for (std::size_t n = rng() % 12; n-- > 0;) b.push_back(words[rng() % words.size()]);
    auto hunks = line_hunks(a, b);
    Lines applied;
    std::size_t next = 0, changed = 0;
    for (std::size_t k = 0; k < hunks.size(); ++k) {
      const Hunk& h = hunks[k];
      // In order, a kept line between each and the one before.
      if (k > 0) {
        ASSERT_LT(next, h.old_begin);
      }
      ASSERT_LE(h.old_begin, h.old_end);
      ASSERT_LE(h.old_end, a.size());
      applied.insert(applied.end(), a.begin() + static_cast<std::ptrdiff_t>(next), a.begin() + static_cast<std::ptrdiff_t>(h.old_begin));
      applied.insert(applied.end(), b.begin() + static_cast<std::ptrdiff_t>(h.new_begin), b.begin() + static_cast<std::ptrdiff_t>(h.new_end));
      changed += (h.old_end - h.old_begin) + (h.new_end - h.new_begin);
      next = h.old_end;
    }
    applied.insert(applied.end(), a.begin() + static_cast<std::ptrdiff_t>(next), a.end());
    ASSERT_EQ(applied, b) << "round " << round;
    ASSERT_EQ(changed, a.size() + b.size() - 2 * common_lines(a, b)) << "round " << round;
  }
}

TEST(LineHunks, PastTheEditLimitTheMiddleIsOneHunk) {
  std::vector<std::string> old_text, new_text;
  for (std::size_t i = 0; i < kMaxEdits; ++i) {
    old_text.push_back("old " + std::to_string(i) + "\n");
    new_text.push_back("new " + std::to_string(i) + "\n");
  }
  Lines a{"first\n"}, b{"first\n"};
  for (const auto& s : old_text) a.push_back(s);
  for (const auto& s : new_text) b.push_back(s);
  a.push_back("last\n");
  b.push_back("last\n");
  auto hunks = line_hunks(a, b);
  ASSERT_EQ(hunks.size(), 1u);
  EXPECT_EQ(hunks[0].old_begin, 1u);
  EXPECT_EQ(hunks[0].old_end, kMaxEdits + 1);
  EXPECT_EQ(hunks[0].new_begin, 1u);
  EXPECT_EQ(hunks[0].new_end, kMaxEdits + 1);
}

}  // namespace
}  // namespace rcxc::lsp
