// The stdlib headers (*.nqh in this folder), embedded in the compiler.
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace rcxc::stdlib {

struct EmbeddedFile {
  std::string_view name;  // e.g. "rcx.nqh"
  std::string_view text;
};

std::span<const EmbeddedFile> files();
std::optional<std::string_view> find(std::string_view name);

}  // namespace rcxc::stdlib
