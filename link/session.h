// The host side of the IR link: send a request, skip the tower's echo, wait
// for the reply, retry with backoff when it is lost or does not check.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <variant>

#include "link/packet.h"
#include "link/transport.h"

namespace rcx {

struct LinkOptions {
  int retries = 30;                // attempts after the first, per request
  Millis reply_grace{150};         // brick think time added to the wire time
  Millis backoff{20};              // first pause before a retry, doubled each time
  Millis max_backoff{400};         // the pause never grows beyond this
  // Seconds a byte takes on the line, for reply timeouts: 2400 baud for real
  // towers; tests against a full-speed virtual brick set it to 0.
  double byte_seconds = kByteSeconds;
};

// Counters a caller can show or a test can check.
struct LinkStats {
  int requests = 0;     // distinct requests sent
  int attempts = 0;     // transmissions, retries included
  int rejected = 0;     // received packets/bytes the decoder rejected
  std::size_t bytes_sent = 0;
};

// What went wrong with one request after every retry.
struct LinkError {
  std::string message;
  bool brick_silent = true;  // no reply at all (vs. only bad replies)
};

struct Link {
  Transport* port = nullptr;
  LinkOptions options;
  LinkStats stats;
  bool toggle = false;  // form of the next distinct request
  // Every session starts with Alive: a brick answers a request equal to the
  // last one it answered (same form) from its cache, and a new host starts
  // with the same toggle form as the previous one did. Alive is harmless to
  // repeat, and after it the next request is always new to the brick.
  bool greeted = false;
  // Called with each rejection reason (for --verbose); may be empty.
  std::function<void(const std::string&)> on_rejected;
};

Link make_link(Transport& port, LinkOptions options = {});

// Sends `request` (opcode in either form; the link picks the toggle) and
// returns the reply payload, whose opcode answers the request.
std::variant<Bytes, LinkError> transact(Link& link, Bytes request);
// Sends a request that has no reply (Set message).
std::variant<std::monostate, LinkError> send_only(Link& link, Bytes request);

// Builds a request payload for `op` with the given field values, in table order
// (a repeated field takes `count` values). Values are written by the table's
// field types, so no caller restates a layout.
Bytes request_payload(const struct OpcodeInfo& op, std::span<const int> values);
// Builds a Transfer data request.
Bytes transfer_payload(int index, std::span<const std::uint8_t> data);
// Reads field `name` of a reply to `op` (the first element of a repeated
// field, or element `element`).
int reply_field(const struct OpcodeInfo& op, std::span<const std::uint8_t> reply, std::string_view name,
                int element = 0);

}  // namespace rcx
