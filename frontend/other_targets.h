// The API names of nqc's other targets (the Scout, the CyberMaster, the
// Spybot, the Swan firmware) that the RCX's API lacks: a program written for one of them fails
// with "not declared", and naming the target saves the reader a search.
#pragma once

#include <optional>
#include <string_view>

namespace rcxc::frontend {

// "Scout", "CyberMaster", "Spybot", "Scout and Spybot" or "Swan firmware"
// when `name` is a name of that target's API and of neither RCX's (the RCX
// 2's included); otherwise none.
std::optional<std::string_view> other_target_of(std::string_view name);

// Whether the lists are sorted, as other_target_of's search needs (tested).
bool other_target_lists_are_sorted();

}  // namespace rcxc::frontend
