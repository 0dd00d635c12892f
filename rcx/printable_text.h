// Text from a file as a message may quote it.
#pragma once

#include <string>
#include <string_view>

#include <fmt/format.h>

namespace rcx {

// Control characters other than a newline and a tab become \xNN, so an
// escape sequence in the file (ESC [2J clears the screen) is shown, not sent
// to the terminal; a backslash stays itself (printable_name in image.h also
// escapes it, for names that must read back unambiguously).
inline std::string printable_text(std::string_view text) {
  std::string out;
  for (char c : text) {
    auto byte = static_cast<unsigned char>(c);
    if ((byte < 0x20 && c != '\n' && c != '\t') || byte == 0x7f) out += fmt::format("\\x{:02x}", byte);
    else out += c;
  }
  return out;
}

}  // namespace rcx
