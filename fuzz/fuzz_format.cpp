// Bytes as NQC source for the formatter (`rcxc format`): a text is either
// refused for its lexing or size, or formatted; the formatter's own re-lex
// check must never fire (that refusal is a layout bug), and the formatted
// text must format to itself. The target aborts otherwise, so libFuzzer
// keeps the input.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>

#include "format/format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto once = rcxc::format::format_source(text);
  if (auto* refusal = std::get_if<rcxc::format::Refusal>(&once)) {
    if (refusal->message.find("layout would change") == std::string::npos) return 0;
    std::fprintf(stderr, "fuzz_format: %s\n", refusal->message.c_str());
    std::abort();
  }
  const std::string& formatted = std::get<std::string>(once);
  auto twice = rcxc::format::format_source(formatted);
  if (!std::holds_alternative<std::string>(twice) || std::get<std::string>(twice) != formatted) {
    std::fprintf(stderr, "fuzz_format: formatting the formatted text changes it again\n");
    std::abort();
  }
  return 0;
}
