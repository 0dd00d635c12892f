// Scenario files: the inputs a run sees, as TOML (format in docs/emulator.md).
//
//   [[input]]
//   at_ms = 500
//   sensor = 1        # 1..3
//   raw = 300         # 0..1023   (or: rotation = <1/16 turns>)
//
//   [[input]]
//   at_ms = 1000
//   message = 7       # 0..255    (or: battery_mv = 7800)
#pragma once

#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "runtime/vm.h"

namespace rcx {

struct ScenarioError {
  std::string message;  // "FILE:LINE: what is wrong"
};

std::variant<std::vector<TimedInput>, ScenarioError> parse_scenario(std::string_view text, std::string_view path);
std::variant<std::vector<TimedInput>, ScenarioError> read_scenario_file(const std::string& path);

}  // namespace rcx
