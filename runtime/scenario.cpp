#include "runtime/scenario.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <toml++/toml.h>

#include "rcx/file_read.h"
#include "tomlfile/read.h"

namespace rcx {
namespace {

using rcxc::toml_read::int_key;
using rcxc::toml_read::TomlError;
using rcxc::toml_read::where;

TimedInput parse_input(const toml::table& t, std::string_view path) {
  static constexpr std::string_view kKeys[] = {"at_ms", "sensor", "raw", "rotation", "message", "battery_mv"};
  for (const auto& [key, node] : t) {
    bool known = false;
    for (auto k : kKeys) known = known || key.str() == k;
    if (!known)
      throw TomlError{fmt::format("{}: unknown key '{}' (expected at_ms, sensor, raw, rotation, message, battery_mv)",
                                  where(path, node), rcxc::toml_read::shown_key(key.str()))};
  }
  std::string here = where(path, t);
  auto at = rcxc::toml_read::at_ms_key(t, path);
  if (!at) throw TomlError{fmt::format("{}: input without 'at_ms'", here)};
  auto sensor = int_key(t, "sensor", 1, 3, path);
  auto raw = int_key(t, "raw", 0, 1023, path);
  auto rotation = int_key(t, "rotation", -32768, 32767, path);
  auto message = int_key(t, "message", 0, 255, path);
  auto battery = int_key(t, "battery_mv", 0, 65535, path);
  int kinds = (raw ? 1 : 0) + (rotation ? 1 : 0) + (message ? 1 : 0) + (battery ? 1 : 0);
  if (kinds != 1)
    throw TomlError{fmt::format("{}: an input needs exactly one of 'raw', 'rotation', 'message', 'battery_mv'", here)};
  if ((raw || rotation) != sensor.has_value())
    throw TomlError{fmt::format("{}: 'sensor' goes with 'raw' or 'rotation' (and only with them)", here)};
  TimedInput in;
  in.at_us = *at * kMicrosPerMs;
  if (raw) in.input = SensorRawInput{static_cast<int>(*sensor) - 1, static_cast<int>(*raw)};
  if (rotation) in.input = RotationInput{static_cast<int>(*sensor) - 1, static_cast<int>(*rotation)};
  if (message) in.input = MessageInput{static_cast<int>(*message)};
  if (battery) in.input = BatteryInput{static_cast<int>(*battery)};
  return in;
}

}  // namespace

std::variant<std::vector<TimedInput>, ScenarioError> parse_scenario(std::string_view text, std::string_view path) {
  // TOML's own words for a binary file are about UTF-8 sequences.
  if (holds_binary_data(text))
    return ScenarioError{fmt::format("{}: holds binary data, not a scenario (a scenario is a TOML file of [[input]] tables)",
                                     path)};
  auto read = rcxc::toml_read::read_toml(text, path, "a scenario is [[input]] tables of keys and numbers");
  if (auto* error = std::get_if<rcxc::toml_read::TomlError>(&read)) return ScenarioError{error->message};
  toml::table root = std::move(std::get<toml::table>(read));
  std::vector<TimedInput> inputs;
  try {
    for (const auto& [key, node] : root) {
      if (key.str() != "input")
        throw TomlError{fmt::format("{}: unknown key '{}' (a scenario is a list of [[input]] tables)",
                                    where(path, node), rcxc::toml_read::shown_key(key.str()))};
      const toml::array* list = node.as_array();
      if (list == nullptr || !list->is_array_of_tables())
        throw TomlError{fmt::format("{}: 'input' must be written as [[input]] tables", where(path, node))};
      for (const auto& item : *list) inputs.push_back(parse_input(*item.as_table(), path));
    }
  } catch (const TomlError& f) {
    return ScenarioError{f.message};
  }
  std::stable_sort(inputs.begin(), inputs.end(), [](const TimedInput& a, const TimedInput& b) { return a.at_us < b.at_us; });
  return inputs;
}

std::variant<std::vector<TimedInput>, ScenarioError> read_scenario_file(const std::string& path) {
  auto file = read_file(path, kScenarioFile);
  if (const auto* problem = std::get_if<FileProblem>(&file)) {
    switch (*problem) {
      case FileProblem::Directory: return ScenarioError{fmt::format("{}: is a directory, not a scenario file", path)};
      case FileProblem::CannotOpen: return ScenarioError{fmt::format("{}: cannot open scenario file: {}", path, cannot_open_reason(path))};
      case FileProblem::ReadError: return ScenarioError{fmt::format("{}: read error", path)};
      case FileProblem::TooLarge: return ScenarioError{too_large_message(path, kScenarioFile)};
    }
  }
  return parse_scenario(std::get<std::string>(file), path);
}

}  // namespace rcx
