#include "nxt/scenario.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "tomlfile/read.h"

namespace nxt {
namespace {

struct Bad {
  std::string message;
};

std::string at(std::string_view path, const toml::node& node) {
  return fmt::format("{}:{}", path, node.source().begin.line);
}

std::optional<std::int64_t> number(const toml::table& t, std::string_view key, std::int64_t lo, std::int64_t hi,
                                   std::string_view path) {
  const toml::node* node = t.get(key);
  if (!node) return std::nullopt;
  auto v = node->value_exact<std::int64_t>();
  if (!v) throw Bad{fmt::format("{}: '{}' must be an integer", at(path, *node), key)};
  if (*v < lo || *v > hi) throw Bad{fmt::format("{}: '{}' = {} is out of range {}..{}", at(path, *node), key, *v, lo, hi)};
  return v;
}

ScenarioInput one_input(const toml::table& t, std::string_view path) {
  static constexpr std::string_view kKeys[] = {"at_ms",    "sensor",     "raw",     "distance_cm",
                                               "rotation", "battery_mv", "message", "mailbox"};
  for (const auto& [key, node] : t) {
    if (std::find(std::begin(kKeys), std::end(kKeys), key.str()) == std::end(kKeys))
      throw Bad{fmt::format("{}: unknown key '{}' (the NXT brick reads at_ms, sensor, raw, distance_cm, rotation, "
                            "battery_mv, message, mailbox)",
                            at(path, node), key.str())};
  }
  auto when = number(t, "at_ms", 0, INT64_MAX / 1000, path);
  if (!when) throw Bad{fmt::format("{}: input without 'at_ms'", at(path, t))};
  auto sensor = number(t, "sensor", 1, 4, path);
  auto raw = number(t, "raw", 0, 1023, path);
  auto distance = number(t, "distance_cm", 0, 255, path);
  auto rotation = number(t, "rotation", INT32_MIN, INT32_MAX, path);
  auto battery = number(t, "battery_mv", 0, 65535, path);
  auto message = number(t, "message", INT32_MIN, INT32_MAX, path);
  auto mailbox = number(t, "mailbox", 1, 10, path);
  bool for_a_port = raw || distance || rotation;
  if ((raw ? 1 : 0) + (distance ? 1 : 0) + (rotation ? 1 : 0) + (battery ? 1 : 0) + (message ? 1 : 0) != 1)
    throw Bad{fmt::format("{}: an input needs exactly one of 'raw', 'distance_cm', 'rotation', 'battery_mv', 'message'",
                          at(path, t))};
  if (sensor.has_value() != for_a_port)
    throw Bad{fmt::format("{}: 'sensor' (1-4) goes with 'raw', 'distance_cm' and 'rotation', not with 'battery_mv' "
                          "or 'message'",
                          at(path, t))};
  if (mailbox && !message) throw Bad{fmt::format("{}: 'mailbox' goes with 'message'", at(path, t))};
  ScenarioInput in;
  in.at_ms = *when;
  if (sensor) in.port = static_cast<int>(*sensor) - 1;
  if (raw) in.raw = static_cast<int>(*raw);
  if (distance) in.distance_cm = static_cast<int>(*distance);
  if (rotation) in.rotation = static_cast<int>(*rotation);
  if (battery) in.battery_mv = static_cast<int>(*battery);
  if (message) in.message = static_cast<std::int32_t>(*message);
  if (mailbox) in.queue = static_cast<int>(*mailbox) - 1;
  return in;
}

}  // namespace

std::variant<std::vector<ScenarioInput>, ScenarioError> parse_scenario(std::string_view text, std::string_view path) {
  auto read = rcxc::toml_read::read_toml(text, path, "an NXT scenario is [[input]] tables of keys and numbers");
  if (auto* error = std::get_if<rcxc::toml_read::TomlError>(&read)) return ScenarioError{error->message};
  toml::table root = std::move(std::get<toml::table>(read));
  std::vector<ScenarioInput> inputs;
  try {
    for (const auto& [key, node] : root) {
      const toml::array* list = node.as_array();
      if (key.str() != "input" || !list || !list->is_array_of_tables())
        throw Bad{fmt::format("{}: a scenario is a list of [[input]] tables", at(path, node))};
      for (const auto& item : *list) inputs.push_back(one_input(*item.as_table(), path));
    }
  } catch (const Bad& b) {
    return ScenarioError{b.message};
  }
  std::stable_sort(inputs.begin(), inputs.end(), [](const auto& a, const auto& b) { return a.at_ms < b.at_ms; });
  return inputs;
}

std::variant<std::vector<ScenarioInput>, ScenarioError> read_scenario_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return ScenarioError{fmt::format("{}: is a directory, not a scenario file", path)};
  std::ifstream in(path, std::ios::binary);
  if (!in) return ScenarioError{fmt::format("{}: cannot read the scenario file", path)};
  // One byte past the cap is enough to refuse: /dev/zero or an endless
  // pipe ends with a message, not with the machine's memory.
  std::string text(kMaxScenarioBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) return ScenarioError{fmt::format("{}: cannot read the scenario file", path)};
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxScenarioBytes)
    return ScenarioError{fmt::format("{}: larger than a scenario file may be (1 MiB); is it the right file?", path)};
  return parse_scenario(text, path);
}

}  // namespace nxt
