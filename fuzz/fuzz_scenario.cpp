// Bytes as text, read two ways: a TOML scenario file and the `@` directives
// of a semantic-test file. The first byte picks the parser, so one corpus
// grows both.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "runtime/scenario.h"
#include "verify/testspec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1) != 0) {
    (void)rcx::parse_scenario(text, "fuzz.toml");
  } else {
    (void)rcx::semtest::parse_spec(text);
  }
  return 0;
}
