// What the virtual NXT's sensors see over time: the `rcxc run` scenario
// format (TOML, docs/emulator.md) with NXT ports 1-4 and the ultrasonic
// distance:
//
//   [[input]]
//   at_ms = 500
//   sensor = 4          # 1..4 (NXT input ports)
//   raw = 300           # 0..1023
//
//   [[input]]
//   at_ms = 800
//   sensor = 2
//   distance_cm = 40    # 0..255, what an ultrasonic sensor on the port reads
//
//   [[input]]
//   at_ms = 900
//   sensor = 3
//   rotation = 16       # an RCX rotation sensor's position, 1/16 turns (ANGLE)
//
//   [[input]]
//   at_ms = 950
//   message = 101       # int32 + NUL into mailbox 1, as a master's MessageWrite
//   mailbox = 1         # 1..10 (optional, default 1)
//
//   [[input]]
//   at_ms = 1000
//   battery_mv = 7200
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace nxt {

struct ScenarioInput {
  std::int64_t at_ms = 0;
  int port = -1;  // 0..3, or -1 for battery and messages
  std::optional<int> raw;
  std::optional<int> distance_cm;
  std::optional<int> battery_mv;
  std::optional<int> rotation;
  std::optional<std::int32_t> message;
  int queue = 0;  // the message's mailbox, 0..9
};

struct ScenarioError {
  std::string message;  // "FILE:LINE: what is wrong"
};

// Inputs in time order.
std::variant<std::vector<ScenarioInput>, ScenarioError> parse_scenario(std::string_view text, std::string_view path);
// A scenario file holds at most this many bytes (as the RCX's scenarios).
inline constexpr std::size_t kMaxScenarioBytes = std::size_t{1} << 20;
std::variant<std::vector<ScenarioInput>, ScenarioError> read_scenario_file(const std::string& path);

}  // namespace nxt
