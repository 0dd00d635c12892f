// "Did you mean": the name a misspelt one most likely stands for.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rcxc::frontend {

// Edits (insert, delete, replace, swap two neighbours) from `a` to `b`; a
// letter differing only in case costs nothing, as `onfwd` is plainly `OnFwd`.
std::size_t spelling_distance(std::string_view a, std::string_view b);

// Names longer than this get no suggestion (closest_name).
inline constexpr std::size_t kMaxSpelledName = 64;

// The candidate nearest to `misspelt`, if it is near enough to be a typing
// slip (a third of the name's length in edits; only case for
// names shorter than three) and no other candidate is as
// near; names starting with "__" (the library's own helpers) are skipped.
// A name longer than kMaxSpelledName gets none.
std::optional<std::string> closest_name(std::string_view misspelt, const std::vector<std::string>& candidates);

// The candidate that is `bare` with a prefix, as TOUCH is SENSOR_TOUCH and
// FWD is OUT_FWD: the shortest one ending in "_" + `bare` (same case), when
// `bare` has three letters or more and no other such candidate is as short.
std::optional<std::string> name_with_prefix(std::string_view bare, const std::vector<std::string>& candidates);

}  // namespace rcxc::frontend
