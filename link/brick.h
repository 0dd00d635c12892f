// The virtual brick: the emulator (runtime/vm.h) answering IR requests the
// way the RCX firmware reference (seeds/000) describes, byte for byte.
//
// `hear` takes bytes as the brick's IR receiver gets them and returns the
// bytes it transmits (framed replies). The protocol state the machine does
// not model lives here: the last request and its reply (the same request in
// the same toggle form again is a retransmission and gets the same reply
// without being executed again: hosts alternate the form between distinct
// requests and start every session with Alive, which is therefore never
// taken for a retransmission), the transfer-data block
// sequence, and the firmware download.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "link/packet.h"
#include "runtime/vm.h"

namespace rcx {

// Line noise: each byte is lost or has one bit flipped with probability p.
struct Noise {
  double probability = 0.0;
  std::mt19937_64 rng{1};
};
Noise make_noise(double probability, std::uint64_t seed);
Bytes apply_noise(Noise& noise, std::span<const std::uint8_t> bytes);

enum class DownloadTarget : std::uint8_t { None, Program, Firmware };

struct BrickProtocol {
  std::optional<Bytes> last_request;  // last request that was answered
  Bytes last_reply;
  DownloadTarget target = DownloadTarget::None;
  int next_block = 1;                 // the sequence number expected next
  // Firmware download: the announced checksum and entry, the running sum.
  int firmware_checksum = 0;
  unsigned firmware_sum = 0;
  bool firmware_ready = false;        // downloaded and checked, awaiting unlock
};

struct BrickCounters {
  int requests = 0;       // packets decoded
  int replies = 0;        // replies sent (retransmissions included)
  int duplicates = 0;     // retransmissions answered from the cache (never Alive)
  int rejected = 0;       // decoder rejections
  int unanswered = 0;     // requests the seed says get no reply
};

struct Brick {
  Machine vm;
  BrickProtocol protocol;
  Decoder decoder = request_decoder();
  BrickCounters counters;
  std::vector<std::string> log;  // why requests were rejected/unanswered (bounded)
  bool trace = false;            // also log every request, reply and broadcast
};

Brick make_brick(Config config = {});

// The reply payload (reply opcode + fields) to one decoded request, or
// nothing when the brick stays silent.
std::optional<Bytes> answer(Brick& brick, std::span<const std::uint8_t> request);

// Bytes in, bytes out: decodes `heard` and returns the framed replies.
Bytes hear(Brick& brick, std::span<const std::uint8_t> heard);

// What the brick transmits on its own: a program's Send message broadcasts a
// Set message request over the infrared link (seed). The framed packets for
// the machine's events from index `first` on (the caller keeps its place).
// Traced as "send" lines in the brick's log, beside the requests and replies.
Bytes broadcasts(Brick& brick, std::size_t first);

}  // namespace rcx
