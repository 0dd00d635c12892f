// Bytes as a .rcx file: read, disassemble, write back, run bounded.
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>

#include "backend/disasm.h"
#include "fuzz/fuzz_run.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto result = rcx::read_image(std::span<const std::uint8_t>(data, size));
  const auto* image = std::get_if<rcx::Image>(&result);
  if (image == nullptr) return 0;
  (void)rcxc::backend::disassemble(*image);
  (void)rcx::write_image(*image);
  rcxc::fuzz::run_bounded(*image);
  return 0;
}
