#include "nxt/scenario.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "tomlfile/read.h"

namespace nxt {
namespace {

using rcxc::toml_read::int_key;
using rcxc::toml_read::TomlError;
using rcxc::toml_read::where;

ScenarioInput one_input(const toml::table& t, std::string_view path) {
  static constexpr std::string_view kKeys[] = {"at_ms",    "sensor",     "raw",     "distance_cm",
                                               "rotation", "battery_mv", "message", "mailbox"};
  for (const auto& [key, node] : t) {
    if (std::find(std::begin(kKeys), std::end(kKeys), key.str()) == std::end(kKeys))
      throw TomlError{fmt::format("{}: unknown key '{}' (the NXT brick reads at_ms, sensor, raw, distance_cm, "
                                  "rotation, battery_mv, message, mailbox)",
                                  where(path, node), rcxc::toml_read::shown_key(key.str()))};
  }
  auto when = rcxc::toml_read::at_ms_key(t, path);
  if (!when) throw TomlError{fmt::format("{}: input without 'at_ms'", where(path, t))};
  auto sensor = int_key(t, "sensor", 1, 4, path);
  auto raw = int_key(t, "raw", 0, 1023, path);
  auto distance = int_key(t, "distance_cm", 0, 255, path);
  auto rotation = int_key(t, "rotation", INT32_MIN, INT32_MAX, path);
  auto battery = int_key(t, "battery_mv", 0, 65535, path);
  auto message = int_key(t, "message", INT32_MIN, INT32_MAX, path);
  auto mailbox = int_key(t, "mailbox", 1, 10, path);
  bool for_a_port = raw || distance || rotation;
  if ((raw ? 1 : 0) + (distance ? 1 : 0) + (rotation ? 1 : 0) + (battery ? 1 : 0) + (message ? 1 : 0) != 1)
    throw TomlError{fmt::format(
        "{}: an input needs exactly one of 'raw', 'distance_cm', 'rotation', 'battery_mv', 'message'", where(path, t))};
  if (sensor.has_value() != for_a_port)
    throw TomlError{fmt::format("{}: 'sensor' (1-4) goes with 'raw', 'distance_cm' and 'rotation', not with "
                                "'battery_mv' or 'message'",
                                where(path, t))};
  if (mailbox && !message) throw TomlError{fmt::format("{}: 'mailbox' goes with 'message'", where(path, t))};
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

// "Permission denied" as the middle of a sentence.
std::string lowercase_first(std::string text) {
  if (!text.empty()) text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
  return text;
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
        throw TomlError{fmt::format("{}: a scenario is a list of [[input]] tables", where(path, node))};
      for (const auto& item : *list) inputs.push_back(one_input(*item.as_table(), path));
    }
  } catch (const TomlError& b) {
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
  if (!in) {
    // Why, as an RCX scenario says it: a mistyped name and a file of
    // another user's read alike as "cannot read".
    int why = errno;
    bool missing = !std::filesystem::exists(std::filesystem::symlink_status(path, ec));
    return ScenarioError{fmt::format("{}: cannot open the scenario file: {}", path,
                                     missing ? std::string("no such file") : lowercase_first(std::strerror(why)))};
  }
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
