#include "stdlib/stdlib.h"

#include <charconv>

namespace rcxc::stdlib {

std::optional<std::string_view> find(std::string_view name) {
  for (const auto& f : files())
    if (f.name == name) return f.text;
  return std::nullopt;
}

std::vector<NamedNumber> defined_numbers(std::string_view prefix) {
  std::vector<NamedNumber> out;
  std::string_view text = find("rcx.nqh").value_or("");
  constexpr std::string_view kDefine = "#define ";
  while (!text.empty()) {
    std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    if (!line.starts_with(kDefine)) continue;
    line.remove_prefix(kDefine.size());
    std::size_t space = line.find(' ');
    if (space == std::string_view::npos || !line.starts_with(prefix)) continue;
    std::string_view name = line.substr(0, space), number = line.substr(space + 1);
    while (!number.empty() && (number.back() == ' ' || number.back() == '\r')) number.remove_suffix(1);
    int base = 10;
    if (number.starts_with("0x")) number.remove_prefix(2), base = 16;
    int value = 0;
    auto [ptr, ec] = std::from_chars(number.data(), number.data() + number.size(), value, base);
    if (ec != std::errc{} || ptr != number.data() + number.size() || number.empty()) continue;  // not a plain number
    out.push_back({std::string(name), value});
  }
  return out;
}

}  // namespace rcxc::stdlib
