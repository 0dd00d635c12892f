// tomlfile/: reading the project's TOML files (the RCX and the NXT scenarios)
// through toml++, with the text toml++ 3.3 faults on refused before it
// parses, and the checks of integer keys both scenario readers share.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include <toml++/toml.h>

namespace rcxc::toml_read {

struct TomlError {
  std::string message;  // "PATH:LINE: what is wrong"
};

// "PATH:LINE" of a node, to begin a message about it.
std::string where(std::string_view path, const toml::node& node);

// A key's name as a message quotes it: a quoted key may spell any
// character ("at\u001b[2J"), and a control character would reach the
// terminal as itself; each is shown as \xNN. Not rcx::printable_text:
// tomlfile/ includes nothing of ours (runtime/ and nxt/ both read TOML
// through it, and nxt/ may not reach rcx/), and a key is shown on one
// line, so a newline and a tab are escaped here where printable_text keeps
// them for multi-line messages.
std::string shown_key(std::string_view key);

// An integer key of `t` in [lo, hi], or nullopt when absent; a value of
// another type or out of range throws TomlError. `open_above`: hi only
// keeps the value from overflowing later, so a value below lo is told
// "lo or more" rather than a range.
std::optional<std::int64_t> int_key(const toml::table& t, std::string_view key, std::int64_t lo, std::int64_t hi,
                                    std::string_view path, bool open_above = false);

// A table's `at_ms` in 0..kLongestRunMs (tomlfile/longest_run.h), or nullopt when absent; throws
// TomlError as int_key does ("must be 0 or more", "is later than the
// longest run (1099511627776 ms, about 35 years)").
std::optional<std::int64_t> at_ms_key(const toml::table& t, std::string_view path);

// The table `text` holds, or what is wrong with it. `what_it_holds` ends
// the message for text refused before parsing ("a scenario is [[input]]
// tables of keys and numbers"): binary data (a NUL in the first 4 KiB),
// and what toml++ would fault on.
std::variant<toml::table, TomlError> read_toml(std::string_view text, std::string_view path,
                                               std::string_view what_it_holds);

}  // namespace rcxc::toml_read
