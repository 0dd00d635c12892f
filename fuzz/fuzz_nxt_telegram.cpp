// Bytes as the virtual NXT hears them on its pty: a Bluetooth byte stream
// reassembled into telegrams, each decoded (as a request and as a reply, as
// the host's -v log does) and answered by one virtual NXT that keeps its
// state (files, handles, mailboxes, I2C) across telegrams, with time moving
// between them. Every reply to a well-formed request must decode again.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "nxt/telegram.h"
#include "nxt/transport.h"
#include "nxt/virtual_nxt.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nxt::VirtualNxt brick = nxt::make_virtual_nxt();
  nxt::FrameReader reader;
  reader.feed(std::span(data, size));
  while (auto telegram = reader.next()) {
    auto decoded = nxt::decode(*telegram);
    if (auto* d = std::get_if<nxt::Decoded>(&decoded)) (void)nxt::describe(*d);
    (void)nxt::decode_reply(*telegram);
    auto reply = nxt::answer(brick, *telegram);
    // A reply to a request of the table must parse (an unknown opcode's
    // 0xBE reply names an opcode the table does not have).
    bool known = std::holds_alternative<nxt::Decoded>(nxt::decode_request(*telegram));
    if (reply && known && !std::holds_alternative<nxt::Decoded>(nxt::decode_reply(*reply))) std::abort();
    nxt::advance_to(brick, brick.now_us + 7'000);
  }
  return 0;
}
