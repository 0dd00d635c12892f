#include "stdlib/stdlib.h"

namespace rcxc::stdlib {

std::optional<std::string_view> find(std::string_view name) {
  for (const auto& f : files())
    if (f.name == name) return f.text;
  return std::nullopt;
}

}  // namespace rcxc::stdlib
