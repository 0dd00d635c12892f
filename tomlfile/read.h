// tomlfile/: reading the project's TOML files (the RCX and the NXT scenarios)
// through toml++, with the text toml++ 3.3 faults on refused before it
// parses. Both scenario readers call read_toml, so the guard is written once.
#pragma once

#include <string>
#include <string_view>
#include <variant>

#include <toml++/toml.h>

namespace rcxc::toml_read {

struct TomlError {
  std::string message;  // "PATH:LINE: what is wrong"
};

// The table `text` holds, or what is wrong with it. `what_it_holds` ends
// the message for text refused before parsing ("a scenario is [[input]]
// tables of keys and numbers").
std::variant<toml::table, TomlError> read_toml(std::string_view text, std::string_view path,
                                               std::string_view what_it_holds);

}  // namespace rcxc::toml_read
