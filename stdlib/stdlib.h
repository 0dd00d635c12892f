// The stdlib headers (*.nqh in this folder), embedded in the compiler.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rcxc::stdlib {

struct EmbeddedFile {
  std::string_view name;  // e.g. "rcx.nqh"
  std::string_view text;
};

std::span<const EmbeddedFile> files();
std::optional<std::string_view> find(std::string_view name);

// `#define NAME NUMBER` lines of rcx.nqh whose NAME starts with `prefix`, in
// file order: the names NQC gives numbers (SOUND_CLICK = 0, ...), so tools
// that print those numbers use the library's spelling, not a copy of it.
struct NamedNumber {
  std::string name;
  int value = 0;
};
std::vector<NamedNumber> defined_numbers(std::string_view prefix);

}  // namespace rcxc::stdlib
