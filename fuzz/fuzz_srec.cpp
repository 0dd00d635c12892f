// Bytes as a firmware S-record file: parsed as `rcxc remote firmware` does.
// Whatever the file says, the firmware must lie in the RCX's RAM from
// 0x8000 (the reader checks every address before storing a byte); the
// target aborts if a parsed firmware breaks that.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <variant>

#include "link/remote.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto result = rcx::parse_srec(std::string(reinterpret_cast<const char*>(data), size));
  const auto* fw = std::get_if<rcx::Firmware>(&result);
  if (fw == nullptr) return 0;
  if (fw->start != 0x8000 || fw->bytes.empty() || fw->bytes.size() > 0x8000 || fw->entry < 0x8000 ||
      fw->entry > 0xffff)
    std::abort();
  return 0;
}
