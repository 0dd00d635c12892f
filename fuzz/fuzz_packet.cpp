// Bytes as what the brick's IR receiver hears: the request decoder and the
// virtual brick answering every packet it decodes. The first byte chooses how
// the rest is fed: raw (noise and all) or framed as one request payload, so
// the brick's request handling is reached without the fuzzer having to learn
// the complement framing first. A reply decoder also sees the bytes, as a
// host waiting for the reply to the framed request would.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "link/brick.h"
#include "link/packet.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> rest(data + 1, size - 1);
  rcx::Brick brick = rcx::make_brick();
  if ((data[0] & 1) != 0) {
    // Several requests, each a length byte then payload, all framed.
    std::size_t at = 0;
    while (at < rest.size()) {
      const std::size_t n = std::min<std::size_t>(rest[at], rest.size() - at - 1);
      const auto payload = rest.subspan(at + 1, n);
      (void)rcx::hear(brick, rcx::frame(payload));
      brick.vm.run_until(brick.vm.now_us() + 100 * rcx::kMicrosPerMs);
      at += n + 1;
    }
  } else {
    (void)rcx::hear(brick, rest);
  }
  if (!rest.empty()) {
    rcx::Decoder reply = rcx::reply_decoder(rest.subspan(0, 1));
    (void)rcx::feed(reply, rest);
  }
  return 0;
}
