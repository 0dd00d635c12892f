#include "runtime/scenario.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <toml++/toml.h>

#include "rcx/file_read.h"

namespace rcx {
namespace {

struct Fail {
  std::string message;
};

std::string where(std::string_view path, const toml::node& node) {
  return fmt::format("{}:{}", path, node.source().begin.line);
}

// The latest at_ms an input can name (its time in µs still fits): later
// than any run goes.
constexpr std::int64_t kNoUpperBound = INT64_MAX / kMicrosPerMs;

// An integer key in [lo, hi], or nullopt when absent.
std::optional<std::int64_t> int_key(const toml::table& t, std::string_view key, std::int64_t lo, std::int64_t hi,
                                    std::string_view path) {
  const toml::node* node = t.get(key);
  if (node == nullptr) return std::nullopt;
  auto v = node->value_exact<std::int64_t>();
  if (!v) throw Fail{fmt::format("{}: '{}' must be an integer", where(path, *node), key)};
  if (hi == kNoUpperBound && *v < lo)
    throw Fail{fmt::format("{}: '{}' = {} must be {} or more", where(path, *node), key, *v, lo)};
  if (*v < lo || *v > hi) throw Fail{fmt::format("{}: '{}' = {} is out of range {}..{}", where(path, *node), key, *v, lo, hi)};
  return v;
}

TimedInput parse_input(const toml::table& t, std::string_view path) {
  static constexpr std::string_view kKeys[] = {"at_ms", "sensor", "raw", "rotation", "message", "battery_mv"};
  for (const auto& [key, node] : t) {
    bool known = false;
    for (auto k : kKeys) known = known || key.str() == k;
    if (!known)
      throw Fail{fmt::format("{}: unknown key '{}' (expected at_ms, sensor, raw, rotation, message, battery_mv)",
                             where(path, node), key.str())};
  }
  std::string here = where(path, t);
  auto at = int_key(t, "at_ms", 0, kNoUpperBound, path);
  if (!at) throw Fail{fmt::format("{}: input without 'at_ms'", here)};
  auto sensor = int_key(t, "sensor", 1, 3, path);
  auto raw = int_key(t, "raw", 0, 1023, path);
  auto rotation = int_key(t, "rotation", -32768, 32767, path);
  auto message = int_key(t, "message", 0, 255, path);
  auto battery = int_key(t, "battery_mv", 0, 65535, path);
  int kinds = (raw ? 1 : 0) + (rotation ? 1 : 0) + (message ? 1 : 0) + (battery ? 1 : 0);
  if (kinds != 1)
    throw Fail{fmt::format("{}: an input needs exactly one of 'raw', 'rotation', 'message', 'battery_mv'", here)};
  if ((raw || rotation) != sensor.has_value())
    throw Fail{fmt::format("{}: 'sensor' goes with 'raw' or 'rotation' (and only with them)", here)};
  TimedInput in;
  in.at_us = *at * kMicrosPerMs;
  if (raw) in.input = SensorRawInput{static_cast<int>(*sensor) - 1, static_cast<int>(*raw)};
  if (rotation) in.input = RotationInput{static_cast<int>(*sensor) - 1, static_cast<int>(*rotation)};
  if (message) in.input = MessageInput{static_cast<int>(*message)};
  if (battery) in.input = BatteryInput{static_cast<int>(*battery)};
  return in;
}

struct TomlTrap {
  int line = 0;  // from 1
  std::string what;
};

bool bare_key_character(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
}

// "[" or "[[" and blanks at the start of `row`, then a character no key
// starts with.
bool header_with_a_bad_key(std::string_view row) {
  std::size_t at = row.find_first_not_of(" \t");
  if (at == std::string_view::npos || row[at] != '[') return false;
  at += at + 1 < row.size() && row[at + 1] == '[' ? 2 : 1;  // "[[" is one token, "[ [" is not
  at = row.find_first_not_of(" \t", at);
  if (at == std::string_view::npos) return true;
  return !bare_key_character(row[at]) && row[at] != '"' && row[at] != '\'';
}

// What in a TOML scenario (keys and numbers only) would reach a fault of
// toml++ 3.3, which the fuzzer found: it classifies some letters (U+0441,
// U+0411) as whitespace or not through __builtin_unreachable (undefined
// behaviour), and asserts on a table header whose key starts with another
// character than a letter, digit, '_', '-' or a quote ("[+", "[[/"): an
// abort in Debug builds. Such text is refused before the parser sees it.
std::optional<TomlTrap> toml_trap(std::string_view text) {
  int line = 1;
  for (std::size_t at = 0; at <= text.size(); ++line) {
    std::size_t end = std::min(text.find('\n', at), text.size());
    std::string_view row = text.substr(at, end - at);
    std::size_t hash = row.find('#');
    bool quoted = row.substr(0, hash).find_first_of("\"'") != std::string_view::npos;
    std::string_view code = quoted ? row : row.substr(0, hash);
    if (std::any_of(code.begin(), code.end(), [](char c) { return static_cast<unsigned char>(c) > 0x7f; }))
      return TomlTrap{line, "a letter that is not ASCII outside a comment"};
    if (header_with_a_bad_key(code)) return TomlTrap{line, "a table header without a name"};
    at = end + 1;
  }
  return std::nullopt;
}

}  // namespace

std::variant<std::vector<TimedInput>, ScenarioError> parse_scenario(std::string_view text, std::string_view path) {
  // TOML's own words for a binary file are about UTF-8 sequences.
  if (holds_binary_data(text))
    return ScenarioError{fmt::format("{}: holds binary data, not a scenario (a scenario is a TOML file of [[input]] tables)",
                                     path)};
  if (auto trap = toml_trap(text))
    return ScenarioError{fmt::format("{}:{}: {} (a scenario is [[input]] tables of keys and numbers)", path,
                                     trap->line, trap->what)};
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    return ScenarioError{fmt::format("{}:{}: {}", path, e.source().begin.line, e.description())};
  }
  std::vector<TimedInput> inputs;
  try {
    for (const auto& [key, node] : root) {
      if (key.str() != "input")
        throw Fail{fmt::format("{}: unknown key '{}' (a scenario is a list of [[input]] tables)", where(path, node), key.str())};
      const toml::array* list = node.as_array();
      if (list == nullptr || !list->is_array_of_tables())
        throw Fail{fmt::format("{}: 'input' must be written as [[input]] tables", where(path, node))};
      for (const auto& item : *list) inputs.push_back(parse_input(*item.as_table(), path));
    }
  } catch (const Fail& f) {
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
      case FileProblem::CannotOpen: return ScenarioError{fmt::format("{}: cannot open scenario file", path)};
      case FileProblem::ReadError: return ScenarioError{fmt::format("{}: read error", path)};
      case FileProblem::TooLarge: return ScenarioError{too_large_message(path, kScenarioFile)};
    }
  }
  return parse_scenario(std::get<std::string>(file), path);
}

}  // namespace rcx
